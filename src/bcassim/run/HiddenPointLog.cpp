#include "bcassim/run/HiddenPointLog.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/coupling/PointUncertainty.h"
#include "bcassim/io/CsvTruncate.h"
#include "bcassim/run/OutputFiles.h"

namespace bcassim {

HiddenPointLog::HiddenPointLog(const Scene& scene, const std::filesystem::path& dir,
                               std::optional<double> resumeStep)
    : scene_(scene),
      path_(dir / "hidden_points.csv"),
      out_(openStepCsv(path_.string(),
                       "step,time_s,point,x_m,y_m,z_m,sigma_x_m,sigma_y_m,sigma_z_m,radius95_m,"
                       "model_error_sigma_m,radius95_total_m",
                       resumeStep)) {}

void HiddenPointLog::add(int step, double time, const MechanicalForecastModel& mean,
                         const Filter& filter, double modelErrorVariance) {
  const Eigen::MatrixX3d p = mean.positionsOf(scene_.hidden.points);
  const std::vector<PointUncertainty> u =
      pointUncertainty(*scene_.model.mesh, scene_.hidden.points, filter.covarianceFactor());
  for (size_t i = 0; i < u.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    // sqrt(chi2 (lambda_max + q)) with radius95 = sqrt(chi2 lambda_max)
    const double total =
        std::sqrt(u[i].radius95 * u[i].radius95 + kChiSquare3At95 * modelErrorVariance);
    out_ << fmt::format(
        "{},{:.9g},{},{:.9g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", step, time,
        i, p(r, 0), p(r, 1), p(r, 2), u[i].sigma(0), u[i].sigma(1), u[i].sigma(2), u[i].radius95,
        std::sqrt(modelErrorVariance), total);
  }
  flushOrThrow(out_, path_);
}

}  // namespace bcassim
