// Internal file-system helpers of the io module, with one-line InputErrors naming the path.
#pragma once
#include <string>

namespace bcassim::io {

// Throws InputError "<path>: cannot open file" unless `path` is an existing regular file.
void requireReadableFile(const std::string& path);

// Creates the parent directory of `path` if missing; throws InputError when it cannot.
void createParentDirectory(const std::string& path);

// The whole content of `path`; throws InputError "<path>: cannot open file" when it is not a
// readable regular file.
std::string readFileBytes(const std::string& path);

// Lower-case extension with its dot, e.g. ".vtu"; empty when none.
std::string lowerExtension(const std::string& path);

}  // namespace bcassim::io
