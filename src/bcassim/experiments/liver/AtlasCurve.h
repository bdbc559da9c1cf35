// A liver's falciform curve from the statistical ligament atlas (thesis §4.3, §5.2, §5.3), for a
// patient whose own ligament is not annotated: the atlas' mean curve and ±σ band transferred onto
// the patient's surface, from a built atlas folder or from one built without that liver.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "bcassim/atlas/LigamentAtlas.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct LeftOutAtlasOptions {
  std::string liverDir;  // annotated livers (NAME.obj + NAME.eseg), as `atlas build` reads them
  double scale = 1e-3;   // m per unit of their files
  std::string exclude;   // the patient's NAME: neither its surface nor its curve enters the atlas
  // The atlas folder: used when it holds a complete atlas built without `exclude`, else built
  // and written there (atomically: a stopped build leaves no folder that looks complete).
  std::string cacheDir;
  int transferIterations = 100;  // L-BFGS iterations of the transfer's registration
};

struct AtlasCurve {
  Eigen::MatrixX3d curve;         // transferred mean curve on the patient's surface, m
  Eigen::VectorXd sigma;          // its per-point standard deviation, m
  Eigen::MatrixX3d lower, upper;  // the band's edges (mean -/+ sigma) on the surface, m
  int atlasLivers = 0;            // livers the atlas was built from (0: read from a folder)
  bool fromCache = false;
  double buildSeconds = 0, transferSeconds = 0;
  double rotationDegrees = 0;  // of the rigid alignment of the atlas' template onto the patient
  std::vector<std::string> poseDoubts;  // that alignment's doubts (RigidAlignment.h's poseDoubts)
};

// patient: the patient's surface in metres (its CT frame). The options are those of the CLI's
// defaults (σ_V 30 mm, σ_W 20 mm, varifold; Fréchet mean with 60 L-BFGS iterations, the
// transfer with 100) and docs/results-atlas.md's recommendations (trimmed per-plane centre,
// projection onto the patient). Throws InputError when the folder has fewer than 2 other livers.
AtlasCurve leftOutAtlasCurve(const TriMesh& patient, const LeftOutAtlasOptions& options,
                             const AtlasLog& log = {});

// The same transfer from an atlas folder written by `bcassim atlas build` (LigamentAtlasFile.h;
// InputError naming the file when it cannot be read), the rigid alignment's rotation limited to
// kScannerFrameMaxRotationDegrees as `atlas transfer` does for CT livers.
AtlasCurve transferredAtlasCurve(const TriMesh& patient, const std::string& atlasDir,
                                 int transferIterations = 100);

// Distances from the points of `curve` to the polyline `reference`, m.
std::vector<double> distancesToPolyline(const Eigen::MatrixX3d& curve,
                                        const Eigen::MatrixX3d& reference);

}  // namespace bcassim
