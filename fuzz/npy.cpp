// libFuzzer target: NumPy .npy arrays through readNpy (header, dtype, shape against the file size).
#include "FuzzInput.h"
#include "bcassim/io/NpyReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bcassim::fuzz::writeInput(data, size, "array.npy");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readNpy(path); });
  return 0;
}
