#include "bcassim/run/StressField.h"

#include <tbb/parallel_for.h>

#include <Eigen/LU>
#include <cmath>

namespace bcassim {

namespace {
Mat3 edges(const TetMesh& mesh, Eigen::Index t, const Eigen::VectorXd* x) {
  Mat3 D;
  auto pos = [&](int a) -> Vec3 {
    const int n = mesh.T(t, a);
    return x ? Vec3(x->segment<3>(3 * n)) : Vec3(mesh.V.row(n).transpose());
  };
  const Vec3 origin = pos(0);
  for (int c = 0; c < 3; ++c) D.col(c) = pos(c + 1) - origin;
  return D;
}
}  // namespace

StressField::StressField(const TetMesh& mesh) : restInverse_(mesh.numTets()) {
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t)
    restInverse_[t] = edges(mesh, t, nullptr).inverse();
}

Eigen::VectorXd StressField::vonMises(const TetMesh& mesh, const TetElasticity& elasticity,
                                      const Eigen::VectorXd& x) const {
  Eigen::VectorXd out(mesh.numTets());
  const bool single = elasticity.numRegions() == 1;
  tbb::parallel_for(Eigen::Index(0), mesh.numTets(), [&](Eigen::Index t) {
    const Mat3 F = edges(mesh, t, &x) * restInverse_[t];
    const Material& material = elasticity.material(single ? 0 : mesh.regionOf(t));
    out(t) = std::visit(
        [&](const auto& m) -> double {
          const double J = F.determinant();
          if (!(J > 0) || !m.admissible(F)) return 0.0;
          const Mat3 sigma = m.pk1(F) * F.transpose() / J;
          const Mat3 s = sigma - sigma.trace() / 3.0 * Mat3::Identity();
          const double vm = std::sqrt(1.5 * s.squaredNorm());
          return std::isfinite(vm) ? vm : 0.0;
        },
        material);
  });
  return out;
}

}  // namespace bcassim
