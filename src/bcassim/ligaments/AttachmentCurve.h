// A ligament's attachment line on the liver surface as an ordered polyline, extracted from the
// edges carrying one .eseg label. Coordinates are those of the surface (millimetres for livers/).
#pragma once
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "bcassim/ligaments/EsegLabels.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct AttachmentCurve {
  std::vector<int> vertices;  // ordered surface vertex ids along the curve
  Eigen::MatrixX3d points;    // #vertices by 3 positions, surface units
  double length = 0;          // polyline length, joining gaps included, surface units
  int components = 0;         // connected pieces of labelled edges
  int joined = 0;             // pieces joined to the longest one (components - 1 when none dropped)
  double gapLength = 0;       // total length of the joining segments, surface units
  int droppedVertices = 0;    // labelled vertices not on the curve (side branches, far pieces)
};

// Each connected piece of edges labelled `label` is reduced to its longest path (exact on trees,
// a close approximation on pieces with cycles: the two-sweep shortest-path diameter); pieces are
// then chained to the longest one, nearest endpoints first, reversing them as needed, unless the
// gap exceeds maxGap (then they are dropped). Starts at the end with the smaller vertex id, so the
// result does not depend on edge order. Throws InputError "<source>: no edge carries label 2".
AttachmentCurve extractAttachmentCurve(const TriMesh& surface, const LabelledEdges& edges,
                                       int label, const std::string& source = "surface",
                                       double maxGap = std::numeric_limits<double>::infinity());

}  // namespace bcassim
