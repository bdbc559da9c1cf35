#include "bcassim/run/SimulationCheckpoint.h"

#include <fmt/format.h>

#include <filesystem>

#include "bcassim/Error.h"
#include "bcassim/io/BinaryArchive.h"

namespace bcassim {
namespace {

std::string pathIn(const std::string& dir) {
  return (std::filesystem::path(dir) / "checkpoint.bin").string();
}

}  // namespace

void writeSimulationCheckpoint(const std::string& dir, const std::string& key,
                               const SimulationCheckpoint& c) {
  ArchiveWriter out(pathIn(dir));
  writeCheckpointHeader(out, "simulation", key);
  for (double x : {static_cast<double>(c.step), c.t, static_cast<double>(c.frames),
                   c.maxNodeDisplacement, c.maxMarkerDisplacement, c.stepSeconds})
    out.number(x);
  out.matrix(c.x);
  out.matrix(c.v);
  out.commit();
}

SimulationCheckpoint readSimulationCheckpoint(const std::string& dir, const std::string& key) {
  const std::string path = pathIn(dir);
  ArchiveReader in = openCheckpoint(path, "simulation", key);
  SimulationCheckpoint c;
  c.step = static_cast<int>(in.number());
  c.t = in.number();
  c.frames = static_cast<int>(in.number());
  c.maxNodeDisplacement = in.number();
  c.maxMarkerDisplacement = in.number();
  c.stepSeconds = in.number();
  c.x = in.matrix().reshaped();
  c.v = in.matrix().reshaped();
  if (c.v.size() != c.x.size())
    throw InputError(fmt::format("{}: damaged (positions and velocities differ in size)", path));
  return c;
}

}  // namespace bcassim
