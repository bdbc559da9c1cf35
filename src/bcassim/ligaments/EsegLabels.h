// Per-edge labels of a triangle surface stored as .eseg files (the annotated livers: 1 background,
// 2 falciform ligament attachment, 3 liver ridge), and the edge numbering these files use.
#pragma once
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

// The surface's undirected edges in .eseg order: faces in order, for face (v0,v1,v2) the edges
// (v0,v1), (v1,v2), (v2,v0); an edge gets the next index the first time it is met. Each entry
// keeps the vertex order of that first visit.
std::vector<std::array<int, 2>> esegEdgeOrder(const TriMesh& surface);

struct LabelledEdges {
  std::vector<std::array<int, 2>> edges;  // #E vertex pairs, .eseg order
  std::vector<int> labels;                // #E labels
};

// Reads one integer per line (blank lines after the last label are allowed) and pairs the labels
// with esegEdgeOrder(surface). Throws InputError naming file and line, e.g.
// "LiTS-3.eseg:5654: expected 5655 edge labels (one per surface edge), the file ends after 5653"
// or "LiTS-3.eseg:12: expected an integer edge label, got 'x'".
LabelledEdges readEseg(const std::string& path, const TriMesh& surface);

// The edges carrying `label`, as vertex pairs (#edges by 2, .eseg order; none: 0 rows).
Eigen::MatrixX2i edgesLabelled(const LabelledEdges& edges, int label);

}  // namespace bcassim
