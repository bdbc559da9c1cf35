// libFuzzer target: STL surfaces (ASCII and binary) through readSurface.
#include "FuzzInput.h"
#include "bcassim/io/SurfaceReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bcassim::fuzz::writeInput(data, size, "input.stl");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readSurface(path); });
  return 0;
}
