// Ligament springs from an attachment curve (thesis §5.1): points sampled along the curve on the
// tet mesh's boundary are extruded along the outward surface normal to fixed anchors; the springs
// are split into groups of contiguous arc length, one set of estimated coefficients per group.
// All lengths in metres.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/mechanics/CubicSpringSet.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

struct LigamentOptions {
  double length = 0.03;  // extrusion distance = rest length, m (thesis: 3 cm, ligament 1.1-4.9 cm)
  double spacing = 0;    // arc length between attachments along the curve, m; 0: the mean
                         // boundary edge length of the mesh
  int numGroups = 4;     // springs sharing coefficients (the estimated parameters)
  // The thesis extrudes "two layers" of springs. Here they are two rows on the surface, offset by
  // +-layerOffset across the curve (the two sides of the ligament's fold); anchors stay fixed
  // points, so a second layer stacked outward (at 2 x length) would act as the same springs.
  int layers = 2;              // 1: springs on the curve itself; 2: the two offset rows
  double layerOffset = 0.004;  // m
  bool smoothNormals = true;   // normal from interpolated vertex normals, else the closest face's
  // A band about the curve (e.g. a ligament atlas' mean -/+ sigma, CarriedCurve::lower/upper):
  // both empty, or as many points as the curve, point i of each across the curve from its point
  // i. Given, the two layers follow its two edges instead of the offsets, so that the springs are
  // spread over where the ligament may be rather than packed about its most likely place; the
  // samples, arc lengths and groups stay those of the curve. Needs layers = 2.
  Eigen::MatrixX3d bandLower, bandUpper;
  CubicSpringCoefficients coefficients;  // initial coefficients of every group
};

struct LigamentSprings {
  CubicSpringSet springs;
  // Per spring, in spring order (layer-major: all of layer 0 along the curve, then layer 1):
  Eigen::MatrixX3d attachments;  // #S by 3 attachment points at rest, on the boundary, m
  Eigen::MatrixX3d normals;      // #S by 3 unit outward normals (anchor = attachment + length n)
  std::vector<double> arc;       // #S arc length along the curve of the sample, m
  double curveLength = 0;        // m
  double maxSnapDistance = 0;    // largest distance from a curve sample to the boundary, m
};

// `curve`: #P by 3 ordered points (m, the mesh's frame; P >= 2), e.g. AttachmentCurve::points
// scaled like the mesh. Samples sit at arc lengths (i + 1/2) L / n, n = max(numGroups,
// round(L / spacing)); sample i belongs to group floor(K s_i / L). Throws InputError for an
// empty mesh, a curve of fewer than 2 points or zero length, a band whose point count is not the
// curve's (or with one layer), or bad options.
LigamentSprings buildLigamentSprings(const TetMesh& mesh, const Eigen::MatrixX3d& curve,
                                     const LigamentOptions& options = {});

}  // namespace bcassim
