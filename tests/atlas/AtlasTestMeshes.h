// Small closed surfaces and random momenta for the atlas tests.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim::test {

// Icosphere of the given radius (m) around `centre`: 20 * 4^level faces, outward.
inline TriMesh makeIcosphere(double radius, int level, const Eigen::Vector3d& centre = {0, 0, 0}) {
  TriMesh m = makeIcosphereSurface(radius, level);
  m.V.rowwise() += centre.transpose();
  return m;
}

// #rows by 3 matrix of independent normal deviates of the given scale.
inline Eigen::MatrixX3d randomMatrix(Eigen::Index rows, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, scale);
  Eigen::MatrixX3d m(rows, 3);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (int c = 0; c < 3; ++c) m(i, c) = n(rng);
  return m;
}

}  // namespace bcassim::test
