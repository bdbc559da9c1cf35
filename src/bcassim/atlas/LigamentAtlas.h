// The statistical atlas of a ligament's attachment curve (thesis §4.3.3, §5.2, Fig. 4.3): rigid
// pre-alignment, Fréchet-mean template (eq. 4.8), every subject's curve carried onto the template,
// statistics over radial cutting planes through the template centre.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "bcassim/atlas/CurveAtlas.h"
#include "bcassim/atlas/Registration.h"
#include "bcassim/atlas/RigidAlignment.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

// One annotated organ: its surface and the ordered attachment curve on it (m, its own frame).
struct AtlasSubject {
  std::string name;
  TriMesh surface;
  Eigen::MatrixX3d curve;
  // Edges (vertex pairs of `surface`; empty when not labelled): the ridge (.eseg label 3), which
  // the multi-object data term matches, and the curve's whole annotated band (every edge of its
  // label; `curve` is the band's longest path), against which predictions are also compared.
  Eigen::MatrixX2i ridge, band;
};

struct LigamentAtlasOptions {
  RegistrationOptions registration;  // kernels, data term, shooting, L-BFGS
  // true: template and momenta estimated jointly (eq. 4.8); false: the initial template is kept
  // and registered onto each subject separately (cheaper, no mean shape).
  bool frechetMean = true;
  int templateSubject = 0;  // subject whose (centred) surface starts the template
  bool rigidAlign = true;   // multi-start ICP of every subject onto the template subject
  // A fit turning a subject further than this is refused as implausible (RigidAlignment.h):
  // kScannerFrameMaxRotationDegrees for CT livers in their scanner's axes (the atlas commands'
  // default); 180 accepts shapes in any orientation.
  double maxRotationDegrees = 180.0;
  // Cutting planes. Radial (falciform, thesis §5.2): they contain the transverse axis (in the
  // template subject's frame) through the template's bounding-box centre; angles cover
  // [-90, 90] degrees around the mean direction of the curves, every planeStepDegrees.
  // Parallel (curves along a flatter surface, e.g. coronary): perpendicular to the transverse
  // axis, every planeSpacing across the template.
  CuttingPlaneFamily::Kind planes = CuttingPlaneFamily::Kind::Radial;
  Eigen::Vector3d transverse = Eigen::Vector3d::UnitX();
  double planeStepDegrees = 5.0;
  double planeSpacing = 0.005;  // m
  // A plane yields a mean point when at least this fraction of the curves crosses it.
  double minCrossingFraction = 0.25;
  // Multi-object data term (MultiObjectDistance.h): the template subject's ridge (.eseg label 3)
  // and each subject's matched along with the surfaces (weight registration.curveWeight).
  bool ridge = false;
  CurveCentre centre = CurveCentre::Mean;    // per-plane centre: mean (thesis), median or Trimmed
  double outlierMads = kDefaultOutlierMads;  // k of the Hampel identifier of CurveCentre::Trimmed
};

struct LigamentAtlas {
  TriMesh templ;  // mean shape (m), in the frame of the centred template subject
  // The template subject's ridge (.eseg label 3) as edges of templ (empty when not labelled), so
  // that a transfer can match a patient's ridge too (template_ridge.csv in the atlas folder).
  Eigen::MatrixX2i templRidge;
  CurveAtlas curve;
  std::vector<std::string> subjects;
  std::vector<Eigen::MatrixX3d> carriedCurves;  // each subject's curve on the template (m)
  std::vector<double> alignmentRms;             // rigid alignment residual per subject (m)
  std::vector<double> data;  // data term D(template flowed onto subject i, subject i)
};

using AtlasLog = std::function<void(const std::string&)>;

// The statistics stage alone: curves already carried onto the template (m, template frame), cut
// by the radial planes of the options around the template's bounding-box centre.
CurveAtlas ligamentCurveAtlas(const TriMesh& templ, const std::vector<Eigen::MatrixX3d>& carried,
                              const LigamentAtlasOptions& options = {});

// Throws InputError on fewer than 2 subjects, a subject without faces or curve points, or a bad
// template index.
LigamentAtlas buildLigamentAtlas(const std::vector<AtlasSubject>& subjects,
                                 const LigamentAtlasOptions& options = {},
                                 const AtlasLog& log = {});

}  // namespace bcassim
