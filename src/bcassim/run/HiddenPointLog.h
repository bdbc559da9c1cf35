// hidden_points.csv of an assimilation run: every step, the predicted position of each hidden
// point (tumour) with its uncertainty from the filter's covariance, and with the model error
// seen in the innovations added (InnovationModelError).
#pragma once
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "bcassim/assimilation/Filter.h"
#include "bcassim/coupling/MechanicalForecastModel.h"
#include "bcassim/run/AssimilationStream.h"
#include "bcassim/scene/Scene.h"

namespace bcassim {

// Each hidden point of the scene: its position in `mean` (the model following the filter's
// mean) and its uncertainty from `filter`. modelErrorVariance: per point, the model error's
// variance per coordinate (m^2; q of InnovationModelError, grown in a free run by
// FreeRunModelError), added isotropically to the covariance for radius95Total (the eigenvalues
// shift by it).
std::vector<HiddenPointPrediction> predictHiddenPoints(const Scene& scene,
                                                       const MechanicalForecastModel& mean,
                                                       const Filter& filter,
                                                       const Eigen::VectorXd& modelErrorVariance);

class HiddenPointLog {
 public:
  // Opens dir/hidden_points.csv: new with its header, or cut back to `resumeStep` and appended
  // to. Throws InputError.
  HiddenPointLog(const std::filesystem::path& dir, std::optional<double> resumeStep);

  // One row per hidden point at `step` (flushed).
  void add(int step, double time, const std::vector<HiddenPointPrediction>& points);

 private:
  std::filesystem::path path_;
  std::ofstream out_;
};

}  // namespace bcassim
