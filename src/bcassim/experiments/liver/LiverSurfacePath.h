// Where a liver's surface comes from: a name in the data folder (LiTS-3, 3Dircadb-18), a path, or
// the built-in phantom.
#pragma once
#include <string>

namespace bcassim {

// A liver given by name is $BCASSIM_DATA/livers/<name>.obj, the data directory defaulting to
// ../shared/data; a path, or "phantom" (kLiverPhantomName), is taken as it is. Throws InputError
// naming the file looked for when there is none.
std::string resolveLiverSurface(const std::string& nameOrPath);

}  // namespace bcassim
