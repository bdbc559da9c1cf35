// libFuzzer target: PLY files (io/PlyReader): the first input byte picks the reader (readSurface,
// readPoints or readCloudFile), the rest is the file.
#include <vector>

#include "FuzzInput.h"
#include "bcassim/io/PointCloudFrames.h"
#include "bcassim/io/PointReader.h"
#include "bcassim/io/SurfaceReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const int choice = data[0] % 3;
  const std::string path = bcassim::fuzz::writeInput(data + 1, size - 1, "input.ply");
  std::vector<std::string> notices;
  bcassim::fuzz::expectOnlyInputErrors([&] {
    if (choice == 0)
      bcassim::readSurface(path);
    else if (choice == 1)
      bcassim::readPoints(path);
    else
      bcassim::readCloudFile(path, notices);
  });
  return 0;
}
