// libFuzzer target: checkpoint archives (io/BinaryArchive): the header and checksum as --resume
// opens them, then texts, numbers and matrices in an order the input chooses (read without the
// checksum, which a mutated file almost never passes).
#include "FuzzInput.h"
#include "bcassim/io/BinaryArchive.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bcassim::fuzz::writeInput(data, size, "checkpoint.bin");
  bcassim::fuzz::expectOnlyInputErrors(
      [&] { bcassim::openCheckpoint(path, "simulation", "fuzz scene"); });
  bcassim::fuzz::expectOnlyInputErrors([&] {
    bcassim::ArchiveReader in(path, "fuzzing");
    for (size_t i = 0; i < 64 && size > 0; ++i) {
      switch (data[i % size] % 3) {
        case 0:
          in.text();
          break;
        case 1:
          in.number();
          break;
        default:
          in.matrix();
          break;
      }
    }
  });
  return 0;
}
