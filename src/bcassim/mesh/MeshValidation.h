// Checks a tetrahedral mesh read from a file before anything computes on it: finite coordinates,
// indices in range, no tet listing a node twice, no tet twice, no unused node, no degenerate or
// inverted tets. Errors name the source and the offending item as the file numbers it.
#pragma once
#include <string>
#include <vector>

#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// Where the nodes and tets of a mesh come from, so that messages name them as the file does (Gmsh
// node tags, VTK cell numbers, lines). Without numbers, items are named by their 0-based index.
struct MeshOrigin {
  std::string source;                  // the file or a name, first in every message
  std::string nodeWord = "node";       // what the file calls a node: "node" (Gmsh), "point" (VTK)
  std::vector<long long> nodeNumbers;  // the file's number of each node; empty: the index
  std::vector<int> nodeLines;          // the line defining each node; empty: unknown
  std::string tetWord = "tet";         // what the file calls a tet: "element" (Gmsh), "cell" (VTK)
  std::vector<long long> tetNumbers;   // the file's number of each tet; empty: the index
  std::vector<int> tetLines;           // the line defining each tet; empty: unknown
};

// Signed volume of tet t, (b-a)x(c-a).(d-a)/6, m^3.
double signedVolume(const TetMesh& mesh, Eigen::Index t);

// Validates `mesh` read from `origin.source` and normalises orientation: if every tet is negatively
// oriented (a file written with the opposite convention) all are flipped; a mesh mixing
// orientations has inverted tets and is rejected. Unused nodes are refused rather than dropped:
// dropping would renumber the nodes that scenes and data files refer to. Throws InputError, e.g.
// "liver.msh:812: element 57 has the same 4 nodes as element 12 (line 767); expected each
// tetrahedron once" or "liver.vtk: tet 17 is inverted (signed volume -1.2e-09 m^3); expected the
// same orientation as the other tets".
void validateTetMesh(TetMesh& mesh, const MeshOrigin& origin);
// The same for a mesh whose items are named by index, e.g. "liver.vtk: tet 17 ...".
void validateTetMesh(TetMesh& mesh, const std::string& source);

}  // namespace bcassim
