// errors.csv and errors_summary.csv of an assimilation or validation run: per step, the
// validation error (ValidationErrors.h) of the estimated and of the initial-parameter model
// against the truth tracks, and its summaries over all steps and over the free run.
#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <fstream>
#include <optional>

#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/run/ValidationErrors.h"
#include "bcassim/scene/Scene.h"

namespace bcassim {

class ValidationLog {
 public:
  // The scene must have assimilation.validation tracks. Opens dir/errors.csv: new with its
  // header, or cut back to `resumeStep` and appended to. Throws InputError.
  ValidationLog(const Scene& scene, const std::filesystem::path& dir,
                std::optional<double> resumeStep);

  // For checkpoints: the four accumulators, 4 numbers each, and back.
  Eigen::MatrixXd saved() const;
  void restore(const Eigen::MatrixXd& m);

  bool hasTruth(int step) const { return truth_.present[static_cast<size_t>(step)]; }

  // Errors of `estimated` and `initial` (validation points, #points by 3, m) at `step`, added to
  // the summaries and written as a row of errors.csv (flushed).
  void add(int step, double time, const Eigen::MatrixX3d& estimated,
           const Eigen::MatrixX3d& initial);

  // Fills result.validated, maxDeformationM, estimated and initial, and writes
  // errors_summary.csv.
  void finish(AssimilationResult& result) const;

 private:
  double percent(double m) const;
  ErrorResult summary(const ErrorSummary& s) const;

  const TrackFrames& truth_;
  int untilStep_;
  std::filesystem::path path_;
  std::ofstream out_;
  double D_ = 0.0;                          // the truth's maximal deformation, m
  ErrorSummary estimated_[2], initial_[2];  // [0] all steps, [1] the free run
};

}  // namespace bcassim
