// libFuzzer target: CSV tables of numbers through readCsvTable.
#include "FuzzInput.h"
#include "bcassim/io/CsvTable.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bcassim::fuzz::writeInput(data, size, "input.csv");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readCsvTable(path); });
  return 0;
}
