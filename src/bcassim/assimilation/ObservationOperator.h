// The observation operator H of eq. 3.1 as the filter sees it: it maps what a forecast exposes
// (its "observable", e.g. node positions) to predicted measurements, fixed once per step at the
// forecast mean (a point cloud's points observe the closest points of the mean's surface).
#pragma once
#include <fmt/format.h>

#include <Eigen/Core>

#include "bcassim/Error.h"
#include "bcassim/assimilation/Observation.h"

namespace bcassim {

// Contract (see also ForecastModel.h): after all forecasts of a step with data are in, the filter
// calls linearize() once, serially, with the mean of the forecasts' observables, weighted as the
// filter weighs its sigma points (ensemble members: equally), and the step's frame; then
// predict() once per forecast, possibly concurrently. With relinearisations
// (FilterOptions::relinearizations) the pair is called again, within the same step, with the
// observables the previous analysis pass moved the mean to. Steps without data call neither. The
// filter knows nothing of what an observable holds: no mesh, no surface.
class ObservationOperator {
 public:
  virtual ~ObservationOperator() = default;

  // Fixes the operator for this step and returns the frame the filter corrects with: the frame's
  // values and noise, with entries the operator cannot use this step marked absent (e.g. points
  // farther from the mean's surface than a robust threshold). Its size is the number of entries
  // predict() writes. Throws InputError when the frame does not fit the operator.
  virtual Observation linearize(const Eigen::VectorXd& meanObservable,
                                const Observation& frame) = 0;

  // The predicted observation of one forecast's observable, by the operator the last linearize()
  // fixed. Const: it may run concurrently for different forecasts.
  virtual void predict(const Eigen::VectorXd& observable, Eigen::VectorXd& predicted) const = 0;
};

// The forecast model's observables are the predicted observations themselves (markers, the test
// models): the identity, the same every step.
class DirectObservation final : public ObservationOperator {
 public:
  // Throws InputError when the frame's size is not the observables'.
  Observation linearize(const Eigen::VectorXd& meanObservable, const Observation& frame) override {
    if (frame.values.size() != meanObservable.size())
      throw InputError(fmt::format("observation frame has {} values, the model predicts {}",
                                   frame.values.size(), meanObservable.size()));
    return frame;
  }
  void predict(const Eigen::VectorXd& observable, Eigen::VectorXd& predicted) const override {
    predicted = observable;
  }
};

}  // namespace bcassim
