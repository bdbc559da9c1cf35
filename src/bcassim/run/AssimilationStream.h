// What an assimilation fed live (bcassim serve) gets instead of the scene's tracks file: the
// markers of each step from a stream, and per step what navigation software shows (the hidden
// points with their 95 % radius, the deformed mesh). runAssimilation calls both on its thread.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace bcassim {

struct StreamedFrame {
  enum class Kind {
    Observed,  // `markers` holds this step's observation
    Missing,   // no frame for this step: a prediction only
    End,       // the stream is over: the run ends after the previous step
  };
  Kind kind = Kind::Missing;
  Eigen::MatrixX3d markers;  // the scene's markers, m; NaN rows for markers not seen
};

struct HiddenPointPrediction {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m, the filter's mean model
  Eigen::Vector3d sigma = Eigen::Vector3d::Zero();     // m, along x, y, z (parameters only)
  double radius95 = 0.0;       // m, from the filter's covariance (PointUncertainty.h)
  double modelErrorSigma = 0;  // m, seen in the innovations (InnovationModelError.h)
  double radius95Total = 0.0;  // m, both: the radius to show
};

struct StepPublication {
  int step = 0;
  double time = 0.0;  // s, the scene's time of the step
  std::vector<HiddenPointPrediction> hidden;
  // The model following the filter's mean: positions (3 #nodes, m) and velocities (3 #nodes,
  // m/s; empty for a static scene). Valid during the call only.
  const Eigen::VectorXd* nodePositions = nullptr;
  const Eigen::VectorXd* nodeVelocities = nullptr;
  // The estimated parameters' mean and standard deviation (physical units, e.g. N/m).
  Eigen::VectorXd parameterMean, parameterStddev;
};

struct AssimilationStream {
  // Called once per step before the filter's step, in order; may block until it knows.
  std::function<StreamedFrame(int step)> frame;
  // Called once per step after it, with the step's predictions.
  std::function<void(const StepPublication&)> publish;
  // Called with each notice the run writes to notices.txt as it goes (a step redone closer to
  // the mean), so that a live log shows it too; may be empty.
  std::function<void(const std::string&)> notice;
};

}  // namespace bcassim
