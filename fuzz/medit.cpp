// libFuzzer target: ASCII Medit meshes (.mesh) through readTetMesh, validation included.
#include "FuzzInput.h"
#include "bcassim/io/MeshReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bcassim::fuzz::writeInput(data, size, "input.mesh");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readTetMesh(path); });
  return 0;
}
