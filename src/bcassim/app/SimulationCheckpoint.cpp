#include "bcassim/app/SimulationCheckpoint.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "bcassim/Error.h"

namespace bcassim {
namespace {

constexpr const char* kMagic = "bcassim simulation checkpoint 1";

std::string pathIn(const std::string& dir) {
  return (std::filesystem::path(dir) / "checkpoint.bin").string();
}

}  // namespace

void writeSimulationCheckpoint(const std::string& dir, const std::string& key,
                               const SimulationCheckpoint& c) {
  const std::string path = pathIn(dir), temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << kMagic << '\n'
        << key << '\n'
        << fmt::format("{} {:.17g} {} {:.17g} {:.17g} {:.17g} {}\n", c.step, c.t, c.frames,
                       c.maxNodeDisplacement, c.maxMarkerDisplacement, c.stepSeconds, c.x.size());
    out.write(reinterpret_cast<const char*>(c.x.data()),
              static_cast<std::streamsize>(sizeof(double) * c.x.size()));
    out.write(reinterpret_cast<const char*>(c.v.data()),
              static_cast<std::streamsize>(sizeof(double) * c.v.size()));
    if (!out) throw InputError(fmt::format("{}: cannot write file", temporary));
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) throw InputError(fmt::format("{}: cannot write file ({})", path, ec.message()));
}

SimulationCheckpoint readSimulationCheckpoint(const std::string& dir, const std::string& key) {
  const std::string path = pathIn(dir);
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(fmt::format("{}: no checkpoint to resume from (run without --resume)", path));
  std::string magic, written, numbers;
  std::getline(in, magic);
  std::getline(in, written);
  std::getline(in, numbers);
  if (magic != kMagic)
    throw InputError(fmt::format("{}: not a bcassim simulation checkpoint", path));
  if (written != key)
    throw InputError(fmt::format("{}: written for another scene ({}); this scene is {}", path,
                                 written, key));
  SimulationCheckpoint c;
  Eigen::Index n = -1;
  std::istringstream fields(numbers);
  fields >> c.step >> c.t >> c.frames >> c.maxNodeDisplacement >> c.maxMarkerDisplacement >>
      c.stepSeconds >> n;
  if (!fields || n < 0) throw InputError(fmt::format("{}: damaged header", path));
  c.x.resize(n);
  c.v.resize(n);
  in.read(reinterpret_cast<char*>(c.x.data()), static_cast<std::streamsize>(sizeof(double) * n));
  in.read(reinterpret_cast<char*>(c.v.data()), static_cast<std::streamsize>(sizeof(double) * n));
  if (!in || !c.x.allFinite() || !c.v.allFinite())
    throw InputError(fmt::format("{}: damaged (expected {} finite positions and velocities)", path,
                                 n));
  return c;
}

}  // namespace bcassim
