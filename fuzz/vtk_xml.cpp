// libFuzzer target: VTK XML files, as .vtu tet meshes through readTetMesh and as .vtp surfaces
// through readSurface.
#include "FuzzInput.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/io/SurfaceReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string grid = bcassim::fuzz::writeInput(data, size, "input.vtu");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readTetMesh(grid); });
  const std::string surface = bcassim::fuzz::writeInput(data, size, "input.vtp");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readSurface(surface); });
  return 0;
}
