// Mesh nodes as points that follow the mesh (MappedPoint with weight 1 on the node), and
// farthest-point sampling of a node set, used for markers, springs and control points.
#pragma once
#include <vector>

#include "bcassim/mesh/BarycentricMap.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// For each node, one tet that uses it (-1 for a node no tet uses).
std::vector<int> tetOfEachNode(const TetMesh& mesh);

// The point at node `node`: a tet holding it (from tetOfEachNode) with weight 1 on it. Throws
// InputError when no tet uses the node.
MappedPoint mappedNode(const TetMesh& mesh, const std::vector<int>& tetOfNode, int node);

// `count` nodes of `nodes` spread over them: the first is the one farthest from their centroid,
// each next one the farthest from those already taken (rest positions). Deterministic; returns
// all of `nodes` when count >= nodes.size(), in the order taken.
std::vector<int> farthestPointSample(const TetMesh& mesh, const std::vector<int>& nodes, int count);

}  // namespace bcassim
