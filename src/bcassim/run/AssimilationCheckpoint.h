// Everything an assimilation run carries from one step to the next, kept beside its outputs so
// that `assimilate --resume` continues a stopped run: the filter's state, the models' reference,
// the random generator of the observation noise, the running summaries.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "bcassim/assimilation/Filter.h"
#include "bcassim/mechanics/MechanicalModel.h"

namespace bcassim {

struct AssimilationCheckpoint {
  int step = 0;  // steps done
  FilterState filter;
  MechanicalState reference;   // the models' reference after the step (analysed mean)
  MechanicalState initialRun;  // the forward run with the initial parameters (validation)
  int initialRunSteps = 0;
  Eigen::MatrixXd errorSummaries;   // ValidationLog's accumulators (empty without validation)
  std::string rng;                  // std::mt19937_64 state of the observation noise
  double innovationSumSquares = 0;  // InnovationModelError
  long innovationEntries = 0;
  // FreeRunModelError: marker motion while observed, hidden points' path since then.
  double motionSumSquares = 0;
  long motionEntries = 0;
  Eigen::MatrixXd freeRunPath, freeRunLast;
  std::vector<double> stepMs;  // wall time of every step so far
  int observedSteps = 0, tangentFailures = 0;
  Eigen::MatrixXd parameters;  // last reported mean and stddev of each parameter (P x 2)
  // InnovationNoiseEstimator (observations.adaptive_noise): its window (k x 3) and estimate, m^2;
  // 0 x 0 and 0 without adaptive noise.
  Eigen::MatrixXd noiseWindow;
  double noiseVariance = 0;
};

// `key` names the scene the checkpoint belongs to; a checkpoint with another key is refused.
// Written through a temporary file and a rename. Throws InputError if it cannot be written.
void writeAssimilationCheckpoint(const std::string& path, const std::string& key,
                                 const AssimilationCheckpoint& checkpoint);
// Throws InputError naming the file when it is missing, damaged or of another scene.
AssimilationCheckpoint readAssimilationCheckpoint(const std::string& path, const std::string& key);

}  // namespace bcassim
