#include "bcassim/calibration/MembraneStrip.h"

#include <fmt/format.h>

#include "bcassim/Error.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim {

namespace {

MechanicalModel makeStripModel(const MembraneOptions& o) {
  auto mesh = std::make_shared<const TetMesh>(makeBoxMesh(o.size, o.cellsX, o.cellsY, o.cellsZ));
  // The density only sizes a mass matrix the static solve does not use.
  return makeMechanicalModel(mesh, {makeMaterial(o.material, o.young, o.poisson)}, 1000.0,
                             MassKind::Lumped);
}

}  // namespace

MembraneStrip::MembraneStrip(const MembraneOptions& options)
    : options_(options), model_(makeStripModel(options)) {
  std::vector<int> clamped;
  for (int k = 0; k <= options.cellsZ; ++k)
    for (int i = 0; i <= options.cellsX; ++i) {
      clamped.push_back(node(i, 0, k));
      pulled_.push_back(node(i, options.cellsY, k));
    }
  // The pulled edge's displacement is (0, t L, 0) at time t in [0, 1] (L the length): solve(d)
  // solves at t = d / L.
  model_.dirichlet = DirichletConditions(
      {{clamped}, {pulled_, Vec3(0, options.size(1), 0), {TimeProfile::Kind::Ramp, 1.0}}},
      *model_.pattern);
  StaticOptions so;
  so.relativeTolerance = options.relativeTolerance;
  solver_ = std::make_unique<StaticSolver>(model_, makeLinearSolver("cholmod"), so);
}

int MembraneStrip::node(int i, int j, int k) const {
  return i + (options_.cellsX + 1) * (j + (options_.cellsY + 1) * k);
}

double MembraneStrip::solve(double d, Eigen::VectorXd& x) {
  if (!(d >= 0.0 && d <= options_.size(1)))
    throw InputError(
        fmt::format("membrane strip: pulled by {:.6g} m; expected 0 to its length {:.6g} m", d,
                    options_.size(1)));
  const double t = d / options_.size(1);
  const StaticReport report = solver_->solve(model_, t, x);
  iterations_ = report.iterations;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  model_.internalForces(t, x, f);
  double R = 0.0;
  for (int p : pulled_) R += f(3 * p + 1);
  return R;
}

}  // namespace bcassim
