// LoadFootprint (a load's force shared by a smooth footprint, issue 14): zero coefficients are the
// load's own split; the in-plane coordinates are centred and of unit RMS radius; the tilts and
// the concentration move and gather the shares exactly as their exponential says.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numeric>

#include "bcassim/Error.h"
#include "bcassim/mechanics/LoadFootprint.h"

namespace bcassim {
namespace {

// A 5 x 5 grid of spacing 2 mm in a plane turned 30 degrees about (1, 1, 0), moved off the
// origin: a zone of 25 surface nodes.
Eigen::MatrixX3d tiltedGrid() {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.5236, Eigen::Vector3d(1, 1, 0).normalized()).matrix();
  Eigen::MatrixX3d P(25, 3);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      P.row(5 * i + j) =
          (R * Eigen::Vector3d(0.002 * i, 0.002 * j, 0.0) + Eigen::Vector3d(0.1, -0.05, 0.02))
              .transpose();
  return P;
}

double sum(const std::vector<double>& s) { return std::accumulate(s.begin(), s.end(), 0.0); }

TEST(LoadFootprint, ZeroCoefficientsGiveTheLoadsOwnSplit) {
  const Eigen::MatrixX3d P = tiltedGrid();
  const LoadFootprint even(P, {});
  for (double s : even.shares()) EXPECT_NEAR(s, 1.0 / 25, 1e-15);
  std::vector<double> base(25);
  for (int k = 0; k < 25; ++k) base[static_cast<size_t>(k)] = 1.0 + k;  // not normalised
  const LoadFootprint weighted(P, base);
  const std::vector<double> s = weighted.shares();
  for (int k = 0; k < 25; ++k) EXPECT_NEAR(s[static_cast<size_t>(k)], (1.0 + k) / 325.0, 1e-15);
}

TEST(LoadFootprint, CoordinatesAreCentredInPlaneAndOfUnitRmsRadius) {
  const LoadFootprint f(tiltedGrid(), {});
  const Eigen::MatrixX2d& uv = f.coordinates();
  EXPECT_LT(uv.colwise().mean().cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(uv.rowwise().squaredNorm().mean(), 1.0, 1e-12);
  // The grid's RMS radius: sqrt(2 x 8e-6) m (each axis' variance: 2 mm^2 x 2 = 8 mm^2).
  EXPECT_NEAR(f.radius(), 0.004, 1e-12);
  EXPECT_LT((f.centre() -
             Eigen::Matrix3d(Eigen::AngleAxisd(0.5236, Eigen::Vector3d(1, 1, 0).normalized())) *
                 Eigen::Vector3d(0.004, 0.004, 0) -
             Eigen::Vector3d(0.1, -0.05, 0.02))
                .norm(),
            1e-12);
}

TEST(LoadFootprint, TiltsAndConcentrationFollowTheirExponential) {
  LoadFootprint f(tiltedGrid(), {});
  const Eigen::MatrixX2d& uv = f.coordinates();
  f.setCoefficient(0, 1.5);
  f.setCoefficient(1, -0.5);
  f.setCoefficient(2, 2.0);
  const std::vector<double> s = f.shares();
  EXPECT_NEAR(sum(s), 1.0, 1e-14);
  for (int i = 0; i < 25; ++i) {
    EXPECT_GT(s[static_cast<size_t>(i)], 0.0);
    const auto e = [&](int k) {
      return 1.5 * uv(k, 0) - 0.5 * uv(k, 1) - 1.0 * uv.row(k).squaredNorm();
    };
    EXPECT_NEAR(std::log(s[static_cast<size_t>(i)] / s[0]), e(i) - e(0), 1e-12);
  }
  // A tilt moves the force's centre towards +u, monotonically; concentration narrows it.
  auto centreU = [&](double tilt) {
    LoadFootprint g(tiltedGrid(), {});
    g.setCoefficient(0, tilt);
    const std::vector<double> t = g.shares();
    double c = 0;
    for (int k = 0; k < 25; ++k) c += t[static_cast<size_t>(k)] * g.coordinates()(k, 0);
    return c;
  };
  EXPECT_NEAR(centreU(0.0), 0.0, 1e-14);
  EXPECT_LT(centreU(0.0), centreU(0.5));
  EXPECT_LT(centreU(0.5), centreU(1.0));
  auto spread = [&](double concentration) {
    LoadFootprint g(tiltedGrid(), {});
    g.setCoefficient(2, concentration);
    const std::vector<double> t = g.shares();
    double r2 = 0;
    for (int k = 0; k < 25; ++k)
      r2 += t[static_cast<size_t>(k)] * g.coordinates().row(k).squaredNorm();
    return r2;
  };
  EXPECT_NEAR(spread(0.0), 1.0, 1e-12);
  EXPECT_LT(spread(1.0), 1.0);
  EXPECT_LT(spread(4.0), spread(1.0));
  // Far out: finite shares summing to 1 (the exponent is shifted before it is taken).
  f.setCoefficient(0, 1e4);
  f.setCoefficient(2, -1e4);
  const std::vector<double> far = f.shares();
  EXPECT_NEAR(sum(far), 1.0, 1e-14);
  for (double v : far) EXPECT_TRUE(std::isfinite(v));
}

TEST(LoadFootprint, AZoneWithoutExtentIsRefused) {
  Eigen::MatrixX3d two(2, 3);
  two << 0, 0, 0, 1, 0, 0;
  try {
    LoadFootprint f(two, {});
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "load footprint: the load has 2 nodes; a footprint needs at least 3");
  }
  const Eigen::MatrixX3d same = Eigen::MatrixX3d::Constant(4, 3, 0.01);
  try {
    LoadFootprint f(same, {});
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "load footprint: the load's nodes coincide; a footprint needs a zone");
  }
}

}  // namespace
}  // namespace bcassim
