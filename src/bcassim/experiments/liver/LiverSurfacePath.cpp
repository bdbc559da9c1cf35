#include "bcassim/experiments/liver/LiverSurfacePath.h"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>

#include "bcassim/Error.h"
#include "bcassim/experiments/liver/LiverScenario.h"

namespace bcassim {

std::string resolveLiverSurface(const std::string& nameOrPath) {
  namespace fs = std::filesystem;
  if (nameOrPath == kLiverPhantomName || fs::exists(nameOrPath)) return nameOrPath;
  if (nameOrPath.find('/') == std::string::npos && fs::path(nameOrPath).extension().empty()) {
    const char* env = std::getenv("BCASSIM_DATA");
    const fs::path data = env && *env ? fs::path(env) : fs::path("../shared/data");
    const fs::path p = data / "livers" / (nameOrPath + ".obj");
    if (fs::exists(p)) return p.string();
    throw InputError(fmt::format("liver '{}': no {} (set BCASSIM_DATA to the data directory)",
                                 nameOrPath, p.string()));
  }
  throw InputError(nameOrPath + ": cannot open file");
}

}  // namespace bcassim
