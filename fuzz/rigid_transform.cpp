// libFuzzer target: 4 x 4 rigid transforms (io/RigidTransformReader, observations.frame_transform)
// in the three formats it reads: the first input byte picks .csv, .txt or .npy, the rest is the
// file.
#include "FuzzInput.h"
#include "bcassim/io/RigidTransformReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const extensions[] = {".csv", ".txt", ".npy"};
  const std::string path =
      bcassim::fuzz::writeInput(data + 1, size - 1, std::string("T") + extensions[data[0] % 3]);
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readRigidTransform(path); });
  return 0;
}
