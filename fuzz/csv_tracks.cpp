// libFuzzer target: marker tracks (time,marker,x,y,z CSV) through readMarkerTracks.
#include "FuzzInput.h"
#include "bcassim/io/CsvTracks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bcassim::fuzz::writeInput(data, size, "tracks.csv");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readMarkerTracks(path); });
  return 0;
}
