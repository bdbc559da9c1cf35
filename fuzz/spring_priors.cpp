// libFuzzer target: the spring priors of `bcassim ligament springs` (springs.yaml) through
// readLigamentSpringPriors, as `liver prepare --spring-priors` reads them.
#include "FuzzInput.h"
#include "bcassim/scene/LigamentSpringPriors.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bcassim::fuzz::writeInput(data, size, "springs.yaml");
  bcassim::fuzz::expectOnlyInputErrors([&] {
    const bcassim::LigamentSpringPriors p = bcassim::readLigamentSpringPriors(path);
    p.forRestLength(0.03);
  });
  return 0;
}
