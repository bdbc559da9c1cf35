// Fitting an incompressible hyperelastic law to a uniaxial curve (thesis eq. 4.9): least squares
// on the nominal stress by Levenberg-Marquardt (Eigen's unsupported module, MINPACK's lmder), with
// parameter bounds, the residual and the parameters' standard errors.
#pragma once
#include <Eigen/Core>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "bcassim/calibration/UniaxialCurve.h"
#include "bcassim/calibration/UniaxialLaw.h"

namespace bcassim {

struct ParameterBound {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
};

struct UniaxialFitOptions {
  // Bounds by parameter name (uniaxialParameterNames), in the parameter's unit; the defaults keep
  // the shear modulus positive: mu > 0 (Neo-Hookean, Ogden), none on c10, c01, alpha.
  std::map<std::string, ParameterBound> bounds;
  int maxEvaluations = 2000;
};

struct UniaxialFitResult {
  UniaxialLaw law = UniaxialLaw::NeoHookean;
  std::vector<std::string> names, units;
  Eigen::VectorXd parameters;
  // Standard errors from the Jacobian at the solution, sqrt(diag(s^2 (J^T J)^-1)) with
  // s^2 = SSR / (n - p); NaN with no more points than parameters.
  Eigen::VectorXd standardErrors;
  Eigen::VectorXd residuals;  // model - measured nominal stress per point, Pa
  double rmsResidual = 0.0;   // Pa
  double rSquared = 0.0;      // 1 - SSR / SST
  double shearModulus = 0.0;  // small-strain, Pa; Young's modulus = 3 x (incompressible)
  int evaluations = 0;
};

// Throws InputError for a bound naming no parameter of the law or with lower >= upper, and
// NumericalError when Levenberg-Marquardt stops without converging (its evaluation budget spent,
// or a non-finite residual).
UniaxialFitResult fitUniaxial(const UniaxialCurve& curve, UniaxialLaw law,
                              const UniaxialFitOptions& options = {});

}  // namespace bcassim
