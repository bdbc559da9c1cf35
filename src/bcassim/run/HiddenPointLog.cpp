#include "bcassim/run/HiddenPointLog.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/coupling/PointUncertainty.h"
#include "bcassim/io/CsvTruncate.h"
#include "bcassim/run/OutputFiles.h"

namespace bcassim {

std::vector<HiddenPointPrediction> predictHiddenPoints(const Scene& scene,
                                                       const MechanicalForecastModel& mean,
                                                       const Filter& filter,
                                                       const Eigen::VectorXd& modelErrorVariance) {
  const Eigen::MatrixX3d p = mean.positionsOf(scene.hidden.points);
  const std::vector<PointUncertainty> u =
      pointUncertainty(*scene.model.mesh, scene.hidden.points, filter.covarianceFactor());
  std::vector<HiddenPointPrediction> out(u.size());
  for (size_t i = 0; i < u.size(); ++i) {
    HiddenPointPrediction& h = out[i];
    h.position = p.row(static_cast<Eigen::Index>(i)).transpose();
    h.sigma = u[i].sigma;
    h.radius95 = u[i].radius95;
    const double q = modelErrorVariance(static_cast<Eigen::Index>(i));
    h.modelErrorSigma = std::sqrt(q);
    // sqrt(chi2 (lambda_max + q)) with radius95 = sqrt(chi2 lambda_max)
    h.radius95Total = std::sqrt(u[i].radius95 * u[i].radius95 + kChiSquare3At95 * q);
  }
  return out;
}

HiddenPointLog::HiddenPointLog(const std::filesystem::path& dir, std::optional<double> resumeStep)
    : path_(dir / "hidden_points.csv"),
      out_(openStepCsv(path_.string(),
                       "step,time_s,point,x_m,y_m,z_m,sigma_x_m,sigma_y_m,sigma_z_m,radius95_m,"
                       "model_error_sigma_m,radius95_total_m",
                       resumeStep)) {}

void HiddenPointLog::add(int step, double time, const std::vector<HiddenPointPrediction>& points) {
  for (size_t i = 0; i < points.size(); ++i) {
    const HiddenPointPrediction& h = points[i];
    out_ << fmt::format(
        "{},{:.9g},{},{:.9g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", step, time,
        i, h.position(0), h.position(1), h.position(2), h.sigma(0), h.sigma(1), h.sigma(2),
        h.radius95, h.modelErrorSigma, h.radius95Total);
  }
  flushOrThrow(out_, path_);
}

}  // namespace bcassim
