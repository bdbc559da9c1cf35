// libFuzzer target: legacy VTK files (.vtk), as tet meshes through readTetMesh and as surfaces
// through readSurface.
#include "FuzzInput.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/io/SurfaceReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bcassim::fuzz::writeInput(data, size, "input.vtk");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readTetMesh(path); });
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readSurface(path); });
  return 0;
}
