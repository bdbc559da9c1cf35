// The statistics of one ligament curve on a template surface (thesis §4.3.3): per cutting plane,
// the mean crossing point projected onto the template and its ±sigma band, stored as barycentric
// coordinates so that they follow any deformation of the template.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/atlas/CurveStatistics.h"
#include "bcassim/atlas/CuttingPlanes.h"
#include "bcassim/atlas/SurfaceAttachment.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct CurveAtlas {
  CuttingPlaneFamily planes;
  std::vector<int> plane;          // plane index of each mean point (planes with enough crossings)
  std::vector<int> count;          // curves crossing that plane
  Eigen::VectorXd sigma;           // standard deviation at each mean point (m), on the template
  SurfaceAttachment mean;          // projected means, in plane order
  SurfaceAttachment lower, upper;  // mean -/+ sigma along the surface within the plane, projected
};

// Positions of the atlas curve on a deformed template, with sigma measured on the carried band
// (half the distance between its lower and upper points).
struct CarriedCurve {
  Eigen::MatrixX3d mean, lower, upper;  // #points by 3 (m)
  Eigen::VectorXd sigma;                // #points (m)
};

// Statistics of curves lying on (or near) the template, in the template's frame (m). A plane
// contributes a mean point when at least minCount curves cross it. Throws InputError when the
// template has no faces or no plane has minCount crossings.
CurveAtlas buildCurveAtlas(const TriMesh& templ, const std::vector<Eigen::MatrixX3d>& curves,
                           const CuttingPlaneFamily& planes, int minCount,
                           CurveCentre centre = CurveCentre::Mean,
                           double outlierMads = kDefaultOutlierMads);

// The atlas curve carried by the template's vertices moved to V (#V by 3, same faces).
CarriedCurve carryCurve(const CurveAtlas& atlas, const Eigen::MatrixX3d& V);

// Mean, lower and upper points moved to their closest points on `surface`, sigma recomputed from
// the moved band. A registration leaves some distance between the deformed template and the
// patient; the ligament is attached to the patient's own surface, so that is where its predicted
// curve belongs. Throws InputError on a surface without faces.
CarriedCurve projectOnto(const CarriedCurve& curve, const TriMesh& surface);

}  // namespace bcassim
