#include "bcassim/run/ValidationLog.h"

#include <fmt/format.h>

#include <limits>
#include <utility>

#include "bcassim/io/CsvTruncate.h"
#include "bcassim/run/OutputFiles.h"

namespace bcassim {

ValidationLog::ValidationLog(const Scene& scene, const std::filesystem::path& dir,
                             std::optional<double> resumeStep)
    : truth_(*scene.assimilation->validationTruth),
      untilStep_(scene.assimilation->observations.untilStep),
      path_(dir / "errors.csv"),
      out_(openStepCsv(path_.string(),
                       "step,time_s,estimated_mean_mm,estimated_max_mm,estimated_mean_pct,"
                       "estimated_max_pct,initial_mean_mm,initial_max_mm,initial_mean_pct,"
                       "initial_max_pct",
                       resumeStep)) {
  D_ = maxDeformation(truth_, scene.validation.rest);
}

Eigen::MatrixXd ValidationLog::saved() const {
  Eigen::MatrixXd m(4, 4);
  const ErrorSummary* all[] = {&estimated_[0], &estimated_[1], &initial_[0], &initial_[1]};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(i, j) = all[i]->saved()[static_cast<size_t>(j)];
  return m;
}

void ValidationLog::restore(const Eigen::MatrixXd& m) {
  ErrorSummary* all[] = {&estimated_[0], &estimated_[1], &initial_[0], &initial_[1]};
  for (int i = 0; i < 4; ++i) all[i]->restore({m(i, 0), m(i, 1), m(i, 2), m(i, 3)});
}

void ValidationLog::add(int step, double time, const Eigen::MatrixX3d& estimated,
                        const Eigen::MatrixX3d& initial) {
  const Eigen::MatrixX3d& truth = truth_.frames[static_cast<size_t>(step)];
  const StepError e = stepError(estimated, truth);
  const StepError i = stepError(initial, truth);
  if (e.points == 0) return;
  const bool free = step > untilStep_;
  estimated_[0].add(e);
  initial_[0].add(i);
  if (free) {
    estimated_[1].add(e);
    initial_[1].add(i);
  }
  out_ << fmt::format("{},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", step,
                      time, 1e3 * e.mean, 1e3 * e.max, percent(e.mean), percent(e.max),
                      1e3 * i.mean, 1e3 * i.max, percent(i.mean), percent(i.max));
  flushOrThrow(out_, path_);
}

void ValidationLog::finish(AssimilationResult& result) const {
  result.validated = true;
  result.maxDeformationM = D_;
  result.estimated = {summary(estimated_[0]), summary(estimated_[1])};
  result.initial = {summary(initial_[0]), summary(initial_[1])};
  const std::filesystem::path path = path_.parent_path() / "errors_summary.csv";
  std::ofstream out = openForWriting(path);
  out << "run,phase,steps,mean_pct,max_pct,mean_mm,max_mm,max_deformation_mm\n";
  const std::pair<const char*, const RunErrors*> runs[] = {{"estimated", &result.estimated},
                                                           {"initial", &result.initial}};
  for (const auto& [name, errors] : runs)
    for (const auto& [phase, e] :
         {std::pair<const char*, ErrorResult>{"all", errors->all},
          std::pair<const char*, ErrorResult>{"free_run", errors->freeRun}})
      out << fmt::format("{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", name, phase, e.steps,
                         e.meanPercent, e.maxPercent, 1e3 * e.meanM, 1e3 * e.maxM, 1e3 * D_);
  flushOrThrow(out, path);
}

double ValidationLog::percent(double m) const {
  if (D_ > 0) return 100 * m / D_;
  return m > 0 ? std::numeric_limits<double>::infinity() : 0.0;
}

ErrorResult ValidationLog::summary(const ErrorSummary& s) const {
  return {s.steps(), s.meanM(), s.maxM(), percent(s.meanM()), percent(s.maxM())};
}

}  // namespace bcassim
