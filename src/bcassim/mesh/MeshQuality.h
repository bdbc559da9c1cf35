// Quality report of a tetrahedral mesh (counts, inverted tets, dihedral angles, volumes, bounding
// box), for logs and for checking generated or loaded meshes. Volumes in m^3, lengths in metres.
#pragma once
#include <Eigen/Core>

#include "bcassim/Types.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

struct MeshQuality {
  Eigen::Index numNodes = 0, numTets = 0;
  Eigen::Index numInverted = 0;                         // tets with negative signed volume
  double minDihedralDeg = 0, maxDihedralDeg = 0;        // over all tets, degrees
  double minVolume = 0, maxVolume = 0;                  // signed, m^3
  double totalVolume = 0;                               // sum of signed volumes, m^3
  Vec3 bboxMin = Vec3::Zero(), bboxMax = Vec3::Zero();  // of the nodes, metres
};

// Smallest and largest of the six dihedral angles of tet abcd, degrees. The angles do not depend
// on orientation; a flat tet gives 0 and 180.
void tetDihedralRangeDeg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double& minDeg,
                         double& maxDeg);

// Assumes node indices are in range (run validateTetMesh on loaded meshes first).
MeshQuality measureQuality(const TetMesh& mesh);

}  // namespace bcassim
