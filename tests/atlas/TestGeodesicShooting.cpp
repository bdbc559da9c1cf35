// Geodesic shooting (eq. 4.4): Hamiltonian conserved to the integrator's order, exact discrete
// adjoint, diffeomorphic flow of a closed surface.
#include <gtest/gtest.h>

#include <cmath>

#include "atlas/AtlasTestMeshes.h"
#include "bcassim/Error.h"
#include "bcassim/atlas/FastExp.h"
#include "bcassim/atlas/GeodesicShooting.h"

namespace bcassim {
namespace {

double hamiltonianDrift(ShootingIntegrator integrator, int steps) {
  const Eigen::MatrixX3d q = test::randomMatrix(20, 0.03, 1);
  const Eigen::MatrixX3d a =
      test::randomMatrix(20, 0.005, 2);  // small enough for the asymptotic regime
  const GeodesicShooting shooting(0.03, {steps + 1, integrator});
  const auto traj = shooting.shoot(q, a, Eigen::MatrixX3d(0, 3));
  const GaussianKernel& k = shooting.kernel();
  return std::abs(k.hamiltonian(traj.back().q, traj.back().a) - k.hamiltonian(q, a)) /
         k.hamiltonian(q, a);
}

TEST(FastExp, MatchesStdExp) {
  for (double x = detail::kFastExpMin; x <= 0.0; x += 0.0137) {
    EXPECT_NEAR(detail::fastExp(x) / std::exp(x), 1.0, 4e-16) << x;
  }
  EXPECT_EQ(detail::fastExp(0.0), 1.0);
}

TEST(GeodesicShooting, HamiltonianConservedToFirstOrderWithEuler) {
  const double e1 = hamiltonianDrift(ShootingIntegrator::Euler, 20);
  const double e2 = hamiltonianDrift(ShootingIntegrator::Euler, 40);
  const double e3 = hamiltonianDrift(ShootingIntegrator::Euler, 80);
  EXPECT_GT(e1, 1e-4);  // the test would be empty if the flow did nothing
  EXPECT_NEAR(std::log2(e1 / e2), 1.0, 0.1);
  EXPECT_NEAR(std::log2(e2 / e3), 1.0, 0.1);
}

TEST(GeodesicShooting, HamiltonianConservedToSecondOrderWithRk2) {
  const double e1 = hamiltonianDrift(ShootingIntegrator::Rk2, 20);
  const double e2 = hamiltonianDrift(ShootingIntegrator::Rk2, 40);
  const double e3 = hamiltonianDrift(ShootingIntegrator::Rk2, 80);
  EXPECT_NEAR(std::log2(e1 / e2), 2.0, 0.2);
  EXPECT_NEAR(std::log2(e2 / e3), 2.0, 0.15);
  EXPECT_GT(e1, 1e-7);
  EXPECT_LT(e1, hamiltonianDrift(ShootingIntegrator::Euler, 20));
}

// L = sum w.x(1) + u.q(1) + z.a(1): pullBack must match central differences in q0, a0, x0.
void checkAdjoint(ShootingIntegrator integrator) {
  const Eigen::MatrixX3d q0 = test::randomMatrix(12, 0.03, 3);
  const Eigen::MatrixX3d a0 = test::randomMatrix(12, 0.02, 4);
  const Eigen::MatrixX3d x0 = test::randomMatrix(30, 0.04, 5);
  const ShootingState c{test::randomMatrix(12, 1.0, 6), test::randomMatrix(12, 1.0, 7),
                        test::randomMatrix(30, 1.0, 8)};
  const GeodesicShooting shooting(0.03, {7, integrator});
  auto loss = [&](const Eigen::MatrixX3d& q, const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& x) {
    const ShootingState s = shooting.shoot(q, a, x).back();
    return (c.q.array() * s.q.array()).sum() + (c.a.array() * s.a.array()).sum() +
           (c.x.array() * s.x.array()).sum();
  };
  const ShootingState g = shooting.pullBack(shooting.shoot(q0, a0, x0), c);
  const double h = 1e-6;
  auto check = [&](const Eigen::MatrixX3d& analytic, int which) {
    double maxErr = 0.0;
    for (Eigen::Index i = 0; i < analytic.rows(); ++i) {
      for (int d = 0; d < 3; ++d) {
        Eigen::MatrixX3d p[3] = {q0, a0, x0}, m[3] = {q0, a0, x0};
        p[which](i, d) += h;
        m[which](i, d) -= h;
        const double fd = (loss(p[0], p[1], p[2]) - loss(m[0], m[1], m[2])) / (2 * h);
        maxErr = std::max(maxErr, std::abs(fd - analytic(i, d)));
      }
    }
    EXPECT_LT(maxErr, 1e-6 * analytic.cwiseAbs().maxCoeff()) << "argument " << which;
  };
  check(g.q, 0);
  check(g.a, 1);
  check(g.x, 2);
}

TEST(GeodesicShooting, PullBackMatchesFiniteDifferencesEuler) {
  checkAdjoint(ShootingIntegrator::Euler);
}
TEST(GeodesicShooting, PullBackMatchesFiniteDifferencesRk2) {
  checkAdjoint(ShootingIntegrator::Rk2);
}

TEST(GeodesicShooting, LargeDeformationKeepsEveryFaceOrientation) {
  const TriMesh sphere = test::makeIcosphere(0.05, 3);
  const Eigen::MatrixX3d q = test::randomMatrix(30, 0.04, 9);
  // Displacements beyond the radius: far larger than this, vertex-only triangles of 4 mm edges
  // fold even though the continuous flow is a diffeomorphism (strains of e^3 at 5 mm).
  const Eigen::MatrixX3d a = test::randomMatrix(30, 0.013, 10);
  // A face keeps its orientation iff its flowed normal n' points the way the flow carries the
  // original normal: n' . (phi(c + eps n) - phi(c)) > 0, which is det(Jacobian) > 0 at face size.
  const Eigen::Index nv = sphere.V.rows(), nf = sphere.F.rows();
  Eigen::MatrixX3d pts(nv + 2 * nf, 3);
  pts.topRows(nv) = sphere.V;
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::RowVector3d v0 = sphere.V.row(sphere.F(f, 0)), v1 = sphere.V.row(sphere.F(f, 1)),
                             v2 = sphere.V.row(sphere.F(f, 2));
    const Eigen::RowVector3d c = (v0 + v1 + v2) / 3.0;
    pts.row(nv + f) = c;
    pts.row(nv + nf + f) = c + 1e-5 * (v1 - v0).cross(v2 - v0).normalized();
  }
  const GeodesicShooting shooting(0.03);  // default: 11 time points, Euler
  const Eigen::MatrixX3d moved = shooting.flow(q, a, pts);
  const double maxDisplacement = (moved.topRows(nv) - sphere.V).rowwise().norm().maxCoeff();
  EXPECT_GT(maxDisplacement, 0.05);  // a large deformation: the radius
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::RowVector3d v0 = moved.row(sphere.F(f, 0)), v1 = moved.row(sphere.F(f, 1)),
                             v2 = moved.row(sphere.F(f, 2));
    const Eigen::RowVector3d n = (v1 - v0).cross(v2 - v0);
    ASSERT_GT(n.dot(moved.row(nv + nf + f) - moved.row(nv + f)), 0.0) << "face " << f;
  }
}

TEST(GeodesicShooting, RejectsBadOptions) {
  EXPECT_THROW(GeodesicShooting(0.0), InputError);
  EXPECT_THROW(GeodesicShooting(0.01, {1, ShootingIntegrator::Euler}), InputError);
}

}  // namespace
}  // namespace bcassim
