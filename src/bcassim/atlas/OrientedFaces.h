// Faces as the oriented points of eq. 4.5: centre c = vertex mean, n = 1/2 (v1 - v0) x (v2 - v0)
// (|n| = area); structure of arrays in Morton order of c, so that far tiles can be skipped.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace bcassim {

struct OrientedFaces {
  std::vector<double> cx, cy, cz;  // centres, #F each (m)
  std::vector<double> nx, ny, nz;  // area-weighted normals, #F each (m^2)
  std::vector<double> invNorm;     // 1 / |n|, 0 for a degenerate face (which then weighs nothing)
  std::vector<int> face;           // row of F of each slot
  Eigen::Index size() const { return static_cast<Eigen::Index>(cx.size()); }
};

// V: #V by 3 positions, F: #F by 3 vertex indices. Throws InputError on an index out of range.
OrientedFaces orientedFaces(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

// Chain rule from face centres and normals to vertices: adds to gV (#V by 3) the gradient of a
// function whose derivatives are gc = d/dc and gn = d/dn (#F by 3 each, rows in the slot order
// of `faces`, which orientedFaces(V, F) built).
void addFaceGradientToVertices(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                               const OrientedFaces& faces, const Eigen::MatrixX3d& gc,
                               const Eigen::MatrixX3d& gn, Eigen::MatrixX3d* gV);

}  // namespace bcassim
