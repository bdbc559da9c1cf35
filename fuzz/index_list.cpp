// libFuzzer target: node and vertex id lists (io/IndexListReader) in the three formats a scene
// may name: the first input byte picks .csv, .txt or .npy, the rest is the file.
#include "FuzzInput.h"
#include "bcassim/io/IndexListReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const extensions[] = {".csv", ".txt", ".npy"};
  const std::string path =
      bcassim::fuzz::writeInput(data + 1, size - 1, std::string("ids") + extensions[data[0] % 3]);
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readIndexList(path); });
  return 0;
}
