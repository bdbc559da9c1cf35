// A liver's falciform curve from the statistical atlas (thesis §5.2, §5.3) built without that
// liver: what `bcassim atlas build LIVERS --exclude NAME --centre trimmed` and `bcassim atlas
// transfer ATLAS NAME.obj --project` give, the atlas (minutes to build) cached in a folder.
#pragma once
#include <Eigen/Core>
#include <string>

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
};

struct LeftOutAtlasCurve {
  Eigen::MatrixX3d curve;  // transferred mean curve on the patient's surface, m
  Eigen::VectorXd sigma;   // its per-point standard deviation, m
  int atlasLivers = 0;     // livers the atlas was built from (0: read from the cache)
  bool fromCache = false;
  double buildSeconds = 0, transferSeconds = 0;
};

// patient: the patient's surface in metres (its CT frame). The options are those of the CLI's
// defaults (σ_V 30 mm, σ_W 20 mm, varifold; Fréchet mean with 60 L-BFGS iterations, the
// transfer with 100) and docs/results-atlas.md's recommendations (trimmed per-plane centre,
// projection onto the patient). Throws InputError when the folder has fewer than 2 other livers.
LeftOutAtlasCurve leftOutAtlasCurve(const TriMesh& patient, const LeftOutAtlasOptions& options,
                                    const AtlasLog& log = {});

}  // namespace bcassim
