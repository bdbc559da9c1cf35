// libFuzzer target: raw camera detections (time,x,y,z CSV, no labels) through readDetectionsCsv,
// as `bcassim track` reads them.
#include "FuzzInput.h"
#include "bcassim/io/DetectionsCsv.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bcassim::fuzz::writeInput(data, size, "detections.csv");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readDetectionsCsv(path); });
  return 0;
}
