// What a filter needs from the world, nothing more: advance one sigma point (or ensemble member)
// one time step and expose what can be observed of it (T of eq. 3.1; H is an
// ObservationOperator over those observables). No FEM here (thesis §3.3).
#pragma once
#include <Eigen/Core>

namespace bcassim {

// The forecast operator of one worker. A filter owns no model: the caller hands it one instance
// per executor worker, and worker w only ever calls instance w, so an implementation needs no
// locks for its own scratch data.
//
// Contract:
//  * The stochastic state is x = [physical part (stateSize() entries); parameters]. The physical
//    part is what the filter estimates of the mechanical state (positions, optionally velocities;
//    may be empty for parameter-only estimation). Everything else the step needs (velocities not
//    carried, the time, loads, contacts) is the model's own "reference", set by endStep().
//  * forecast() must be a function of (reference, state, params) only: forecasts of different
//    sigma points of one step are independent and may run concurrently on different instances
//    and in any order. Running the same inputs twice must give the same outputs.
//  * endStep() is called on every instance, serially, once the step's analysis is done, with the
//    analysed mean. The model moves its reference to the next time step: the next forecasts start
//    from this mean (with parameter-only estimation, the model continues its mechanical state
//    with the analysed parameters, e.g. by re-running the step or keeping the forecast closest to
//    the mean). ETKF members each carry their own physical part, but any quantity kept only in
//    the reference is shared by all members: carry in the state whatever should differ per member.
//  * With FilterOptions::firstSigmaPointAlone, the first forecast of each step returns before any
//    other forecast of that step starts; it runs on instance 0 (with star sigma points it is the
//    mean itself). A model may therefore factorise its system matrix during the first forecast
//    after endStep() and share it, read-only, as a preconditioner with the other instances
//    (thesis Alg. 4/5); how they share it is the model's business.
//  * forecast() also writes the forecast's observable: whatever the step's observation operator
//    (ObservationOperator.h) maps to predicted measurements. With the default DirectObservation
//    it is the predicted observation itself; an operator that must be fixed at the forecast
//    mean (a point cloud observing the mean's surface) gets, e.g., node positions, and is
//    linearised by the filter once all forecasts of the step are in, before any prediction.
//  * Errors are thrown (NumericalError for a diverged step); the filter does not catch them.
class ForecastModel {
 public:
  virtual ~ForecastModel() = default;

  // Size of the physical part of the stochastic state; 0 for parameter-only estimation.
  virtual Eigen::Index stateSize() const = 0;
  // Number of entries of a forecast's observable (e.g. 3 x markers, or 3 x nodes).
  virtual Eigen::Index observableSize() const = 0;

  // Advances one time step from the reference, with the physical part overridden by `state`
  // (stateSize()) and parameters `params` (physical values, already transformed). Writes the new
  // physical part (stateSize()) and the observable at the new time (observableSize()). The
  // observable comes with the forecast because, with a parameter-only state, only the model
  // knows the positions it just computed.
  virtual void forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                        Eigen::VectorXd& newState, Eigen::VectorXd& observable) = 0;

  // The step is over: `state` and `params` (physical values) are the analysed mean.
  virtual void endStep(const Eigen::VectorXd& state, const Eigen::VectorXd& params) = 0;

  // Within a step, after its forecasts (an iterated analysis, RoukfOptions::reforecasts): the
  // step's next forecasts are to start from the model at these analysed values, at the step's
  // own time (a static model: its equilibrium with these parameters becomes the reference, and
  // the forecasts linearise about it), and endStep() still ends this same step. Called like
  // endStep(): on every instance, serially, in worker order; every instance answers alike.
  // Returns whether forecasts about these values can change the analysis: false where the model
  // cannot re-centre (the default, changing nothing: a dynamic step has no such reference), or
  // where its forecasts were already exact about them (a linear response); the reference may
  // then have moved all the same.
  virtual bool recentre(const Eigen::VectorXd& /*state*/, const Eigen::VectorXd& /*params*/) {
    return false;
  }
};

}  // namespace bcassim
