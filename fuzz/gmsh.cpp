// libFuzzer target: Gmsh meshes (.msh formats 1, 2.2 and 4.1) through readTetMesh, validation
// included.
#include "FuzzInput.h"
#include "bcassim/io/MeshReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bcassim::fuzz::writeInput(data, size, "input.msh");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readTetMesh(path); });
  return 0;
}
