// Fréchet-mean atlas (eq. 4.8): exact gradient in template vertices and momenta, and a mean of
// deformed spheres that fits them better than the initial template.
#include <gtest/gtest.h>

#include "atlas/AtlasTestMeshes.h"
#include "bcassim/Error.h"
#include "bcassim/atlas/ControlPoints.h"
#include "bcassim/atlas/FrechetMeanAtlas.h"
#include "bcassim/atlas/GeodesicShooting.h"

namespace bcassim {
namespace {

std::vector<TriMesh> deformedSpheres(const TriMesh& base, const RegistrationOptions& o, int n) {
  const Eigen::MatrixX3d q0 = regularGridControlPoints(base.V, o.sigmaV);
  const GeodesicShooting shooting(o.sigmaV, o.shooting);
  std::vector<TriMesh> shapes;
  for (int i = 0; i < n; ++i) {
    TriMesh s = test::makeIcosphere(0.05, 2);
    s.V = shooting.flow(q0, test::randomMatrix(q0.rows(), 0.002, 50 + i), s.V);
    shapes.push_back(s);
  }
  return shapes;
}

TEST(FrechetMeanAtlas, GradientMatchesFiniteDifferences) {
  RegistrationOptions o;
  o.sigmaV = 0.04;
  o.sigmaW = 0.02;
  o.shooting.timePoints = 5;
  const TriMesh tmpl = test::makeIcosphere(0.05, 1);
  const std::vector<TriMesh> shapes = deformedSpheres(tmpl, o, 2);
  const AtlasObjective objective(tmpl, shapes, o);
  const Eigen::Index nv = tmpl.V.rows(), nq = objective.controlPoints().rows();
  Eigen::MatrixX3d x(nv + 2 * nq, 3);
  x.topRows(nv) = tmpl.V + test::randomMatrix(nv, 0.001, 61);
  x.bottomRows(2 * nq) = test::randomMatrix(2 * nq, 0.002, 62);
  Eigen::MatrixX3d g;
  objective.evaluate(x, &g);
  const double h = 1e-7;
  double maxErrV = 0.0, maxErrA = 0.0;
  for (Eigen::Index i = 0; i < x.rows(); i += 2) {
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixX3d p = x, m = x;
      p(i, c) += h;
      m(i, c) -= h;
      const double fd = (objective.evaluate(p, nullptr) - objective.evaluate(m, nullptr)) / (2 * h);
      (i < nv ? maxErrV : maxErrA) = std::max(i < nv ? maxErrV : maxErrA, std::abs(fd - g(i, c)));
    }
  }
  EXPECT_LT(maxErrV, 1e-6 * g.topRows(nv).cwiseAbs().maxCoeff());
  EXPECT_LT(maxErrA, 1e-6 * g.bottomRows(2 * nq).cwiseAbs().maxCoeff());
}

TEST(FrechetMeanAtlas, MeanFitsTheShapesBetterThanTheTemplate) {
  RegistrationOptions o;
  o.sigmaV = 0.03;
  o.sigmaW = 0.015;
  o.lbfgs.maxIterations = 40;
  const TriMesh tmpl = test::makeIcosphere(0.05, 2);
  const std::vector<TriMesh> shapes = deformedSpheres(tmpl, o, 3);
  const AtlasResult r = buildFrechetMeanAtlas(tmpl, shapes, o);
  EXPECT_LT(r.objective, 0.2 * r.initialObjective);
  EXPECT_EQ(r.momenta.size(), 3u);
  EXPECT_EQ(r.mean.F, tmpl.F);
  EXPECT_THROW(buildFrechetMeanAtlas(tmpl, {}, o), InputError);
}

}  // namespace
}  // namespace bcassim
