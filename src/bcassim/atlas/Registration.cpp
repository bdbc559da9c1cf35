#include "bcassim/atlas/Registration.h"

#include <fmt/format.h>

#include "bcassim/Error.h"
#include "bcassim/atlas/ControlPoints.h"
#include "bcassim/atlas/MultiObjectDistance.h"
#include "bcassim/atlas/RegistrationObjective.h"

namespace bcassim {
namespace {
// Momenta are optimised as one vector, row after row.
Eigen::VectorXd flatten(const Eigen::MatrixX3d& m) {
  Eigen::VectorXd v(m.size());
  for (Eigen::Index i = 0; i < m.rows(); ++i) v.segment<3>(3 * i) = m.row(i).transpose();
  return v;
}
Eigen::MatrixX3d unflatten(const Eigen::VectorXd& v) {
  Eigen::MatrixX3d m(v.size() / 3, 3);
  for (Eigen::Index i = 0; i < m.rows(); ++i) m.row(i) = v.segment<3>(3 * i).transpose();
  return m;
}
}  // namespace

RegistrationResult registerSurface(const TriMesh& source, const TriMesh& target,
                                   const RegistrationOptions& options, const CurvePair* curves) {
  if (source.F.rows() == 0 || target.F.rows() == 0) {
    throw InputError("registration: source and target need triangles");
  }
  const std::unique_ptr<SurfaceDistance> data = makeDataTerm(target, options, curves);
  const SurfaceDistance& distance = *data;
  const GeodesicShooting shooting(options.sigmaV, options.shooting);
  Eigen::MatrixX3d q0 = options.controlPoints.rows() > 0
                            ? options.controlPoints
                            : regularGridControlPoints(source.V, options.sigmaV);
  const double weight =
      options.dataWeight > 0.0 ? options.dataWeight : 1.0 / (options.sigmaW * options.sigmaW);
  const RegistrationObjective objective(source, distance, shooting, q0, weight);

  Eigen::MatrixX3d a0 = Eigen::MatrixX3d::Zero(q0.rows(), 3);
  if (options.initialMomenta.rows() > 0) {
    if (options.initialMomenta.rows() != q0.rows()) {
      throw InputError(fmt::format("registration: {} initial momenta for {} control points",
                                   options.initialMomenta.rows(), q0.rows()));
    }
    a0 = options.initialMomenta;
  }
  LbfgsOptions lbfgs = options.lbfgs;
  if (lbfgs.firstStepMaxNorm <= 0.0) lbfgs.firstStepMaxNorm = 0.05 * options.sigmaV;

  RegistrationResult r;
  r.initialData = distance.value(source.V, source.F);
  const LbfgsResult opt = minimizeLbfgs(
      [&](const Eigen::VectorXd& x, Eigen::VectorXd* g) {
        Eigen::MatrixX3d gm;
        const double value = objective.evaluate(unflatten(x), &gm).total;
        *g = flatten(gm);
        return value;
      },
      flatten(a0), lbfgs);
  r.momenta = unflatten(opt.x);
  const RegistrationTerms terms = objective.evaluate(r.momenta);
  r.controlPoints = std::move(q0);
  r.deformedVertices = objective.deform(r.momenta);
  r.data = terms.data;
  r.regularity = terms.regularity;
  r.iterations = opt.iterations;
  r.evaluations = opt.evaluations;
  r.converged = opt.converged;
  return r;
}

}  // namespace bcassim
