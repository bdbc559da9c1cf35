#include "bcassim/cli/AssimilationProgressBar.h"

namespace bcassim {

void AssimilationProgressBar::update(const AssimilationProgress& p) {
  line_.update(p.step, p.steps, p.elapsedSeconds, p.meanStepMs, p.freeRun ? " (free run)" : "",
               "  " + p.estimate);
}

}  // namespace bcassim
