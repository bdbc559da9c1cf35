// The liver experiment at the smallest size the tests use (the built-in phantom, 700/1,200
// nodes, a few steps): for tests of how scenes are made, not of what they estimate.
#pragma once
#include "bcassim/experiments/liver/LiverScenario.h"

namespace bcassim::test {

inline LiverScenarioOptions smallLiverOptions(int groups = 3, int steps = 6) {
  LiverScenarioOptions o;
  o.surface = kLiverPhantomName;
  o.coarseNodes = 700;
  o.fineNodes = 1200;
  o.groups = groups;
  o.steps = steps;
  o.observedSteps = steps * 2 / 3;
  return o;
}

}  // namespace bcassim::test
