#include "bcassim/cli/ProgressBar.h"

#include <fmt/format.h>

namespace bcassim {

void ProgressBar::update(const RunProgress& p) {
  const std::string variant =
      p.numVariants > 1 ? fmt::format(" ({} {}/{})", p.variant, p.variantIndex + 1, p.numVariants)
                        : std::string();
  line_.update(p.stepsDone, p.stepsTotal, p.elapsedSeconds, p.meanStepMs, variant, "");
}

}  // namespace bcassim
