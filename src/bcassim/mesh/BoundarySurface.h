// Boundary surface of a tetrahedral mesh: the faces that belong to exactly one tet, oriented
// outward, with rest normals. Basis of surface regions, marker projection and rendering.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mesh/TetMesh.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct BoundarySurface {
  Eigen::MatrixX3i F;              // #F by 3 tet-mesh node indices, counter-clockwise from outside
  Eigen::VectorXi faceTet;         // #F owning tet of each face
  std::vector<int> nodes;          // sorted, unique tet-mesh node ids on the surface
  Eigen::MatrixX3d faceNormals;    // #F by 3 unit outward normals at rest (zero for a flat face)
  Eigen::MatrixX3d vertexNormals;  // #V by 3 (#V of the tet mesh) area-weighted unit outward
                                   // normals at rest; zero rows for interior nodes
};

// Faces are matched by sorting their node triples, O(#T log #T). Face order: by owning tet, then
// by the tet's local face. Throws InputError when a face is shared by more than two tets (the
// mesh is not a manifold) or a node index is out of range.
BoundarySurface extractBoundary(const TetMesh& mesh);

// The boundary as a stand-alone triangle mesh with compact vertex numbering: vertex i is tet-mesh
// node boundary.nodes[i] (that vector is the map back), faces are boundary.F renumbered.
TriMesh toTriMesh(const TetMesh& mesh, const BoundarySurface& boundary);

}  // namespace bcassim
