#include "bcassim/calibration/SpringCalibration.h"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/assimilation/Executor.h"
#include "bcassim/assimilation/RoukfFilter.h"
#include "bcassim/calibration/LatticeForecast.h"

namespace bcassim {
namespace {

void checkOptions(const SpringCalibrationOptions& o) {
  const MembraneOptions& m = o.membrane;
  const char* names[3] = {"width", "length", "thickness"};
  for (int a = 0; a < 3; ++a)
    if (!(std::isfinite(m.size(a)) && m.size(a) > 0))
      throw InputError(
          fmt::format("membrane {}: expected a length > 0 m, got {}", names[a], m.size(a)));
  if (!(o.strain > 0 && o.strain <= 1))
    throw InputError(fmt::format("strain: expected a value in (0, 1], got {}", o.strain));
  if (o.frames < 1 || o.passes < 1)
    throw InputError(
        fmt::format("frames and passes: expected >= 1, got {} and {}", o.frames, o.passes));
  if (o.latticeX < 1 || o.latticeY < 1 || m.cellsX % o.latticeX != 0 || m.cellsY % o.latticeY != 0)
    throw InputError(fmt::format("lattice {} x {} cells: must divide the membrane's {} x {} cells",
                                 o.latticeX, o.latticeY, m.cellsX, m.cellsY));
  if (!(o.forceSigma > 0) || !(o.positionSigma >= 0))
    throw InputError(
        fmt::format("observation sigmas: expected force > 0 and position >= 0, got "
                    "{} and {}",
                    o.forceSigma, o.positionSigma));
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The reactions (N) of the lattice with unit k_alpha, k_beta, k_gamma at positions x: the
// reaction is linear in the coefficients at fixed positions.
Eigen::RowVector3d unitReactions(const LatticeStretch& stretch, const Eigen::VectorXd& x) {
  return {stretch.reaction({1, 0, 0}, x), stretch.reaction({0, 1, 0}, x),
          stretch.reaction({0, 0, 1}, x)};
}

// Least squares c of A c = b with columns scaled to unit norm.
Eigen::VectorXd scaledLeastSquares(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  Eigen::VectorXd scale = A.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < scale.size(); ++c)
    if (scale(c) == 0) scale(c) = 1;
  const Eigen::MatrixXd As = A * scale.cwiseInverse().asDiagonal();
  return As.colPivHouseholderQr().solve(b).cwiseQuotient(scale);
}

// The lattice's reaction (N) at each displacement (m), frames solved in order from rest.
std::vector<double> reactionCurve(const SpringLattice& lattice, const CubicSpringCoefficients& k,
                                  const std::vector<double>& displacements) {
  LatticeStretch stretch(lattice);
  Eigen::VectorXd x = lattice.restPositions();
  std::vector<double> R;
  R.reserve(displacements.size());
  for (double d : displacements) R.push_back(stretch.solve(k, d, x));
  return R;
}

// Ka, Kb, Kg of F(d) = Ka d^3 + Kb d^2 + Kg d fitted to the reactions, with only the terms of
// `terms` (bit 0: Ka, 1: Kb, 2: Kg; the others 0).
Eigen::Vector3d cubicFit(const std::vector<double>& d, const std::vector<double>& F,
                         int terms = 7) {
  std::vector<int> used;
  for (int c = 0; c < 3; ++c)
    if (terms & (1 << c)) used.push_back(c);
  Eigen::MatrixXd A(d.size(), used.size());
  Eigen::VectorXd b(d.size());
  for (size_t i = 0; i < d.size(); ++i) {
    for (size_t u = 0; u < used.size(); ++u) A(i, u) = std::pow(d[i], 3 - used[u]);
    b(i) = F[i];
  }
  const Eigen::VectorXd c = scaledLeastSquares(A, b);
  Eigen::Vector3d K = Eigen::Vector3d::Zero();
  for (size_t u = 0; u < used.size(); ++u) K(used[u]) = c(u);
  return K;
}

double fitResidual(const std::vector<double>& d, const std::vector<double>& F,
                   const Eigen::Vector3d& K) {
  double ss = 0;
  for (size_t i = 0; i < d.size(); ++i)
    ss += std::pow(((K(0) * d[i] + K(1)) * d[i] + K(2)) * d[i] - F[i], 2);
  return std::sqrt(ss / d.size());
}

// The subset of terms whose fit has every coefficient >= 0 and the smallest residual.
int nonNegativeTerms(const std::vector<double>& d, const std::vector<double>& F) {
  int best = 4;  // Kg alone: >= 0 for a reaction that grows
  double bestResidual = std::numeric_limits<double>::infinity();
  for (int terms = 1; terms < 8; ++terms) {
    const Eigen::Vector3d K = cubicFit(d, F, terms);
    if ((K.array() < 0).any()) continue;
    const double r = fitResidual(d, F, K);
    if (r < bestResidual) best = terms, bestResidual = r;
  }
  return best;
}

}  // namespace

SpringCalibrationResult calibrateSprings(const SpringCalibrationOptions& options) {
  checkOptions(options);
  const MembraneOptions& mo = options.membrane;
  SpringCalibrationResult out;

  // The truth: the membrane pulled frame by frame from rest.
  MembraneStrip membrane(mo);
  out.membraneTets = membrane.mesh().numTets();
  out.membraneNodes = membrane.mesh().numNodes();
  const SpringLattice lattice(mo.size, options.latticeX, options.latticeY, 1);
  out.latticeNodes = lattice.numNodes();
  for (const LatticeSpring& s : lattice.springs())
    ++(s.diagonal ? out.diagonalSprings : out.edgeSprings);
  const int rx = mo.cellsX / options.latticeX, ry = mo.cellsY / options.latticeY;
  std::vector<int> atLattice(lattice.numNodes());  // membrane node of each lattice node
  for (int k = 0; k <= 1; ++k)
    for (int j = 0; j <= options.latticeY; ++j)
      for (int i = 0; i <= options.latticeX; ++i)
        atLattice[lattice.node(i, j, k)] = membrane.node(rx * i, ry * j, k * mo.cellsZ);

  const double length = mo.size(1);
  std::vector<double> displacements;
  std::vector<Eigen::VectorXd> truth;  // membrane positions at the lattice nodes, per frame
  out.frames.resize(options.frames);
  Eigen::VectorXd x = membrane.restPositions();
  for (int f = 0; f < options.frames; ++f) {
    SpringFrame& frame = out.frames[f];
    frame.strain = options.strain * (f + 1) / options.frames;
    frame.displacement = frame.strain * length;
    displacements.push_back(frame.displacement);
    const auto t0 = Clock::now();
    frame.membraneReaction = membrane.solve(frame.displacement, x);
    frame.membraneSeconds = secondsSince(t0);
    frame.membraneIterations = membrane.lastIterations();
    Eigen::VectorXd sample(3 * lattice.numNodes());
    for (int p = 0; p < lattice.numNodes(); ++p)
      sample.segment<3>(3 * p) = x.segment<3>(3 * atLattice[p]);
    truth.push_back(std::move(sample));
  }
  double maxReaction = 0;
  for (size_t f = 0; f < out.frames.size(); ++f) {
    if (!(out.frames[f].membraneReaction > 0))
      throw NumericalError(fmt::format("membrane: reaction {:.6g} N at frame {}: not in tension",
                                       out.frames[f].membraneReaction, f + 1));
    maxReaction = std::max(maxReaction, out.frames[f].membraneReaction);
  }

  // The filter's start: the reactions of the lattice placed at the membrane's positions, linear in
  // the coefficients, fitted by least squares. k_gamma and a positive k_alpha are estimated in log
  // space (they stay positive); k_beta, which a softening law makes negative, as it is (the law
  // made one that never pushes, LatticeForecast::coefficients).
  LatticeStretch stretch(lattice);
  Eigen::MatrixXd A(options.frames, 3);
  Eigen::VectorXd b(options.frames);
  for (int f = 0; f < options.frames; ++f) {
    A.row(f) = unitReactions(stretch, truth[f]);
    b(f) = out.frames[f].membraneReaction;
  }
  Eigen::Vector3d k0 = scaledLeastSquares(A, b);
  if (!(k0(2) > 0)) {  // no positive linear term: start from the linear spring alone
    k0.setZero();
    k0(2) = std::max(A.col(2).dot(b) / A.col(2).squaredNorm(), 1e-12);
  }
  const CubicSpringCoefficients admissible = LatticeForecast::coefficients(k0);
  k0 << admissible.kAlpha, admissible.kBeta, admissible.kGamma;
  // Extension of a spring along the length at the largest strain: the scale of each term.
  const double delta = options.strain * length / options.latticeY;
  const double forceScale = std::max(
      {std::abs(k0(0)) * delta * delta * delta, std::abs(k0(1)) * delta * delta, k0(2) * delta});
  std::vector<Parameter> params;
  const char* names[3] = {"k_alpha", "k_beta", "k_gamma"};
  for (int c = 0; c < 3; ++c) {
    if ((c == 0 || c == 2) && k0(c) > 0)
      params.push_back({names[c], k0(c), 0.5 * k0(c), ParameterTransform::exponential()});
    else
      params.push_back({names[c], k0(c), 0.5 * forceScale / std::pow(delta, 3 - c),
                        ParameterTransform::identity()});
  }
  out.initial = {k0(0), k0(1), k0(2)};
  for (int c = 0; c < 3; ++c) out.initialStddev(c) = params[c].stddev;

  // ROUKF over the frames, `passes` times.
  const StochasticState layout({}, {}, params);
  LatticeForecast model(lattice, displacements);
  SerialExecutor serial;
  RoukfFilter filter(layout, {&model}, serial);
  const auto& freeNodes = model.stretch().freeNodes();
  Observation y;
  y.values.resize(model.observableSize());
  y.variance.resize(model.observableSize());
  y.variance.tail(y.variance.size() - 1)
      .setConstant(options.positionSigma > 0 ? options.positionSigma * options.positionSigma : 1.0);
  if (options.positionSigma <= 0) {
    y.present.assign(y.values.size(), false);
    y.present[0] = true;
  }
  for (int step = 0; step < options.passes * options.frames; ++step) {
    const int f = model.frame();
    y.values(0) = out.frames[f].membraneReaction;
    y.variance(0) = std::pow(options.forceSigma * out.frames[f].membraneReaction, 2);
    for (size_t i = 0; i < freeNodes.size(); ++i)
      y.values.segment<3>(1 + 3 * i) = truth[f].segment<3>(3 * freeNodes[i]);
    const FilterStepReport r = filter.step(y);
    out.stepFrame.push_back(f);
    out.stepMean.push_back(r.mean.head<3>());
    out.stepStddev.push_back(r.stddev.head<3>());
  }
  out.estimated = LatticeForecast::coefficients(out.stepMean.back());
  out.stddev = out.stepStddev.back();

  // The estimated lattice pulled like the membrane, timed: a lattice frame takes milliseconds, so
  // the stretch is repeated kTimingRepeats times and each frame keeps its median time.
  constexpr int kTimingRepeats = 5;
  std::vector<std::vector<double>> latticeSeconds(options.frames);
  for (int repeat = 0; repeat < kTimingRepeats; ++repeat) {
    Eigen::VectorXd xl = lattice.restPositions();
    for (int f = 0; f < options.frames; ++f) {
      SpringFrame& frame = out.frames[f];
      const auto t0 = Clock::now();
      frame.latticeReaction = stretch.solve(out.estimated, frame.displacement, xl);
      latticeSeconds[f].push_back(secondsSince(t0));
      frame.latticeIterations = stretch.iterations();
    }
  }
  // Then under the membrane's reaction.
  Eigen::VectorXd xf = lattice.restPositions();
  double sumError = 0, sumAttachment = 0;
  int counted = 0, countedAttachment = 0;
  std::vector<char> pulled(lattice.numNodes(), 0);
  for (int p : stretch.pulledNodes()) pulled[p] = 1;
  for (int f = 0; f < options.frames; ++f) {
    SpringFrame& frame = out.frames[f];
    frame.latticeSeconds = median(latticeSeconds[f]);
    out.maxReactionError =
        std::max(out.maxReactionError,
                 std::abs(frame.latticeReaction - frame.membraneReaction) / frame.membraneReaction);
    // Secant on the grip's displacement until the lattice carries the membrane's reaction.
    double d0 = frame.displacement, R0 = stretch.solve(out.estimated, d0, xf);
    double d1 = d0 * frame.membraneReaction / R0;
    for (int it = 0;; ++it) {
      const double R1 = stretch.solve(out.estimated, d1, xf);
      if (std::abs(R1 - frame.membraneReaction) <= 1e-8 * frame.membraneReaction) break;
      if (it == 50 || R1 == R0)
        throw NumericalError(fmt::format(
            "spring lattice: no grip displacement carries the membrane's {:.6g} N at frame {}",
            frame.membraneReaction, f + 1));
      const double next = d1 + (frame.membraneReaction - R1) * (d1 - d0) / (R1 - R0);
      d0 = d1, R0 = R1;
      d1 = std::clamp(next, 0.0, length);
    }
    frame.forceDrivenDisplacement = d1;
    for (int p = 0; p < lattice.numNodes(); ++p) {
      const double e = (xf.segment<3>(3 * p) - truth[f].segment<3>(3 * p)).norm();
      frame.meanError += e / lattice.numNodes();
      frame.maxError = std::max(frame.maxError, e);
      sumError += e;
      ++counted;
      if (!pulled[p]) continue;
      frame.attachmentMeanError += e / stretch.pulledNodes().size();
      frame.attachmentMaxError = std::max(frame.attachmentMaxError, e);
      sumAttachment += e;
      ++countedAttachment;
    }
    out.maxError = std::max(out.maxError, frame.maxError);
    out.attachmentMaxError = std::max(out.attachmentMaxError, frame.attachmentMaxError);
  }
  out.meanError = sumError / counted;
  out.attachmentMeanError = sumAttachment / countedAttachment;
  out.lastMembrane = truth.back();
  out.lastLattice = xf;
  std::vector<double> fem, msm, femIteration, msmIteration;
  for (const SpringFrame& f : out.frames) {
    fem.push_back(1e3 * f.membraneSeconds);
    msm.push_back(1e3 * f.latticeSeconds);
    femIteration.push_back(fem.back() / std::max(f.membraneIterations, 1));
    msmIteration.push_back(msm.back() / std::max(f.latticeIterations, 1));
  }
  out.membraneMedianMs = median(fem);
  out.latticeMedianMs = median(msm);
  out.speedRatio = out.membraneMedianMs / out.latticeMedianMs;
  out.membraneMedianMsPerIteration = median(femIteration);
  out.latticeMedianMsPerIteration = median(msmIteration);
  out.iterationSpeedRatio = out.membraneMedianMsPerIteration / out.latticeMedianMsPerIteration;

  // Priors per metre of width: the cubic fit of the estimated lattice's reaction curve, and its
  // spread over the symmetric sigma points of the filter's covariance (in its own space).
  const double width = mo.size(0);
  const std::vector<double> R = reactionCurve(lattice, out.estimated, displacements);
  const Eigen::Vector3d fit = cubicFit(displacements, R);
  out.perMetreFitError = fitResidual(displacements, R, fit) / maxReaction;
  const int terms = nonNegativeTerms(displacements, R);
  const Eigen::Vector3d fitNonNegative = cubicFit(displacements, R, terms);
  out.perMetreNonNegativeFitError = fitResidual(displacements, R, fitNonNegative) / maxReaction;
  const Eigen::VectorXd u = filter.mean();
  const Eigen::Matrix3d P = filter.covariance();
  const Eigen::Matrix3d S = P.llt().matrixL();
  Eigen::Vector3d var = Eigen::Vector3d::Zero(), varNonNegative = Eigen::Vector3d::Zero();
  for (int c = 0; c < 3; ++c)
    for (int sign : {-1, 1}) {
      const Eigen::VectorXd us = u + sign * std::sqrt(3.0) * S.col(c);
      Eigen::VectorXd phys;
      layout.physicalParameters(us, phys);
      const std::vector<double> Rs =
          reactionCurve(lattice, LatticeForecast::coefficients(phys), displacements);
      var += (cubicFit(displacements, Rs) - fit).cwiseAbs2() / 6.0;
      varNonNegative += (cubicFit(displacements, Rs, terms) - fitNonNegative).cwiseAbs2() / 6.0;
    }
  for (int c = 0; c < 3; ++c) {
    out.perMetre[c] = {fit(c) / width, std::sqrt(var(c)) / width};
    out.perMetreNonNegative[c] = {fitNonNegative(c) / width, std::sqrt(varNonNegative(c)) / width};
  }
  return out;
}

}  // namespace bcassim
