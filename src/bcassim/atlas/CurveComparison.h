// Distance between a predicted ligament curve and an expert one (thesis §5.2, Table 5.1): per
// cutting plane crossed by both, and from every expert point to the predicted polyline.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/atlas/CuttingPlanes.h"

namespace bcassim {

struct CurveDistance {
  int planes = 0;          // planes crossed by both curves
  double planeMean = 0.0;  // mean distance between the two crossings of such a plane (m)
  double planeMax = 0.0;   // largest of them (m)
  double pointMean = 0.0;  // mean distance of the expert points to the predicted polyline (m)
  double pointMax = 0.0;   // largest of them (m)
};

// Distance from point p to the polyline (rows in order; one row: that point).
double distanceToPolyline(const Eigen::Vector3d& p, const Eigen::MatrixX3d& polyline);

// expert, predicted: ordered polylines (m). A curve crossing a plane more than once contributes
// its crossing nearest to the other curve's crossings. Throws InputError on an empty curve.
CurveDistance compareCurves(const Eigen::MatrixX3d& expert, const Eigen::MatrixX3d& predicted,
                            const CuttingPlaneFamily& planes);

// The same against the expert's whole annotated band instead of one path through it: band =
// edges (vertex pairs of V) carrying the curve's label. A plane counts when the band and the
// predicted curve both cross it; its distance is from the predicted crossing to the nearest
// crossing of a band edge (a strip of mesh edges crosses a plane about once per edge across its
// width, so a prediction inside the band is within about half an edge of one); the point
// distances are from every band vertex. Throws
// InputError on an empty band or curve, or an edge index out of range.
CurveDistance compareCurveToBand(const Eigen::MatrixX3d& V, const Eigen::MatrixX2i& band,
                                 const Eigen::MatrixX3d& predicted,
                                 const CuttingPlaneFamily& planes);

}  // namespace bcassim
