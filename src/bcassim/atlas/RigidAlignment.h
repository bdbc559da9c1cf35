// Rigid pre-alignment before the LDDMM registration of thesis §4.3 (the atlas removes position
// and orientation, keeps shape): Procrustes for paired points, ICP for surfaces.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "bcassim/atlas/CurvePair.h"
#include "bcassim/mesh/RigidTransform.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

// Rotation (det +1) and translation minimising sum |R p_i + t - q_i|^2: kabschFit() of
// mesh/PointSetAlignment.h with equal weights, under the name the atlas code uses. P, Q: #P by 3,
// #P >= 3. Throws InputError on mismatched or too few rows.
RigidTransform procrustes(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q);

struct IcpOptions {
  int maxIterations = 50;
  double tolerance = 1e-10;  // stop when the RMS closest-point distance changes by less (m)
};

// Rigid transform taking the source surface onto the target: centroids matched first, then
// point-to-closest-point ICP from the source vertices to the target surface.
RigidTransform alignRigidly(const TriMesh& source, const TriMesh& target,
                            const IcpOptions& options = {});

// The livers of CT scans lie in their scanner's patient axes: one is never turned by more than
// this from another (55 shared livers onto a template: at most 67 degrees, except LiTS-9, whose
// multi-start picked 166 degrees, the ligament on the wrong side: its curve 153 mm from the
// expert's). A fit turned further is an implausible pose.
inline constexpr double kScannerFrameMaxRotationDegrees = 90.0;

// What alignRigidlyMultiStart chose, the better fit it refused, if any, and a rival pose that
// fits as well.
struct MultiStartReport {
  double rms = 0.0;              // m, RMS closest-point distance of the returned transform
  bool withCurve = false;        // a curve on both surfaces was fitted too (rms is of both)
  double rotationDegrees = 0.0;  // angle of the returned rotation
  bool rejected = false;         // a start turned more than allowed fitted >= 1 % better, refined
  double rejectedRms = 0.0, rejectedRotationDegrees = 0.0;
  // Another allowed pose at least kRivalPoseDegrees away fits within 3 %, or better (the surface
  // alone cannot tell them apart: LiTS-9 onto three livers, two poses 54 deg apart, 9.3 mm RMS
  // each, its curve 27 or 93 mm off). The returned pose stays the multi-start's choice; the closest
  // rival's fit and both agreements with the target's signed principal axes (SignedAxes below)
  // are for the user, who knows the orientation.
  bool ambiguous = false;
  double rivalRms = 0.0, rivalApartDegrees = 0.0;
  double axesAgreement = 0.0, rivalAxesAgreement = 0.0;  // axesAgreement() of each
};

inline constexpr double kRivalPoseDegrees = 30.0;

// Fraction of a curve's points the rigid fit uses at each iteration, the closest (trimmed ICP):
// experts label as much of a ridge as each CT shows, so one liver's may run on past the other's
// end, and those points would pull the pose. Leave-one-out on the 55 shared livers (held-out
// ridge used): all points 8.5 mm mean, but one liver 41 mm off; 80 %: 8.7 mm, worst 25 mm.
inline constexpr double kCurveKeptFraction = 0.8;

// The report's doubts as lines for the user (none when the pose is clear): a better fit refused
// beyond maxRotationDegrees, a rival pose that fits alike.
std::vector<std::string> poseDoubts(const MultiStartReport& report, double maxRotationDegrees);

// A surface's principal axes (area-weighted, columns by decreasing variance), each pointing
// towards its longer tail (the sign of the third moment along it), with that skewness. On the
// shared CT livers the thinnest axis is the most skewed (0.29-0.38: the organ is a wedge), the
// longest one next (0.04-0.29, right lobe to left), whatever the CT's frame.
struct SignedAxes {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d skewness = Eigen::Vector3d::Zero();  // standardised third moments, >= 0
};
SignedAxes signedAxes(const TriMesh& surface);

// How well rotation R carries the source's signed axes onto the target's: sum over the axes of
// cos(angle) weighted by the smaller skewness of the pair (an axis whose sign the shape does not
// fix weighs nothing).
double axesAgreement(const SignedAxes& source, const SignedAxes& target, const Eigen::Matrix3d& R);

// Angle of a rotation matrix, degrees in [0, 180].
double rotationAngleDegrees(const Eigen::Matrix3d& R);

// Like alignRigidly, but ICP is started from each of the 24 rotations that map the coordinate
// axes onto themselves (about the centroid) and the best start (smallest RMS distance after
// `probeIterations`) is refined: shapes scanned in different orientations still align. The
// identity wins ties. rmsOut (optional) receives the final RMS closest-point distance (m).
// Starts whose probe turned the source by more than maxRotationDegrees are taken only when no
// other is left (180: any orientation); `report` says what was chosen and refused, and whether
// a rival pose fits alike (up to three more starts refined).
// curves (optional): a curve drawn on both surfaces (edges of each, the livers' ridge) fitted
// too, each source curve vertex to its closest point on the target curve (the closest
// kCurveKeptFraction of them at each iteration), their mean squared distance weighted
// curveWeight times the surface's; every start is then judged by both, and the RMS (rmsOut, the
// report's) is sqrt((surface MSD + curveWeight curve MSD) / (1 + curveWeight)). Where the
// surface alone leaves two poses alike (MultiStartReport::ambiguous), the curve can tell them
// apart. Throws InputError on a negative or non-finite curveWeight, or a curve edge naming a
// vertex its surface does not have.
RigidTransform alignRigidlyMultiStart(const TriMesh& source, const TriMesh& target,
                                      const IcpOptions& options = {}, int probeIterations = 8,
                                      double* rmsOut = nullptr, double maxRotationDegrees = 180.0,
                                      MultiStartReport* report = nullptr,
                                      const CurvePair* curves = nullptr, double curveWeight = 1.0);

// Isotropic scale factor that gives `source` the surface area of `target`: sqrt(area(target) /
// area(source)). Size normalisation before registration (as in Procrustes analysis with
// scaling): the registration is then left with shape differences only. Throws InputError when
// either surface has zero area.
double areaMatchingScale(const TriMesh& source, const TriMesh& target);

}  // namespace bcassim
