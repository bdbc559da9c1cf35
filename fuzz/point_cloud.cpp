// libFuzzer target: point sets as observations take them: the first input byte picks the reader
// (a point-cloud frame file as .txt, .csv or .npy; a whole-sequence cloud CSV; readPoints on
// .txt, .csv or .npy), the rest is the file.
#include <vector>

#include "FuzzInput.h"
#include "bcassim/io/PointCloudFrames.h"
#include "bcassim/io/PointReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const extensions[] = {".txt", ".csv", ".npy"};
  const int choice = data[0] % 7;
  const std::string path = bcassim::fuzz::writeInput(
      data + 1, size - 1, std::string("cloud") + extensions[choice < 6 ? choice % 3 : 1]);
  std::vector<std::string> notices;
  bcassim::fuzz::expectOnlyInputErrors([&] {
    if (choice < 3) {
      bcassim::readCloudFile(path, notices);
    } else if (choice < 6) {
      bcassim::readPoints(path);
    } else {
      bool byTime = false;
      bcassim::readCloudCsv(path, byTime, notices);
    }
  });
  return 0;
}
