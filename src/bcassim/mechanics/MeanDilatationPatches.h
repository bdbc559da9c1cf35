// Patches of face-adjacent tets over which the volumetric (lambda) term of the material is averaged
// (mean dilatation, Nagtegaal et al. 1974): fewer volume constraints, so linear tets stop locking
// when the Poisson ratio nears 0.5.
#pragma once
#include <vector>

#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

struct MeanDilatationPatches {
  std::vector<std::vector<int>> tets;   // tets of each patch, all in one region
  std::vector<std::vector<int>> nodes;  // distinct nodes of each patch, sorted
  // local[p][4 * k + a] = position in nodes[p] of node a of tets[p][k].
  std::vector<std::vector<int>> local;

  int numPatches() const { return static_cast<int>(tets.size()); }
};

// Greedy, deterministic partition: walking the tets in index order, each tet not yet taken starts
// a patch that grows over face neighbours of the same region, each time by the one adding the
// fewest new nodes (compact patches, small stiffness fill), until it holds `patchTets` tets. A tet
// left alone (all neighbours taken) joins a neighbouring patch of its region. patchTets = 1 gives
// one patch per tet (the plain element). Throws InputError for patchTets < 1.
MeanDilatationPatches makeMeanDilatationPatches(const TetMesh& mesh, int patchTets);

}  // namespace bcassim
