#include "bcassim/mechanics/MeanDilatationPatches.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <map>

#include "bcassim/Error.h"

namespace bcassim {
namespace {

// Face neighbours of every tet (up to 4, -1 for a boundary face).
std::vector<std::array<int, 4>> faceNeighbours(const TetMesh& mesh) {
  const Eigen::Index nt = mesh.numTets();
  std::vector<std::array<int, 4>> nb(nt, {-1, -1, -1, -1});
  std::map<std::array<int, 3>, std::pair<int, int>> open;  // sorted face -> (tet, local face)
  for (Eigen::Index t = 0; t < nt; ++t)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> key;
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != f) key[j++] = mesh.T(t, k);
      std::sort(key.begin(), key.end());
      auto [it, inserted] = open.try_emplace(key, static_cast<int>(t), f);
      if (!inserted) {
        nb[t][f] = it->second.first;
        nb[it->second.first][it->second.second] = static_cast<int>(t);
        open.erase(it);
      }
    }
  return nb;
}

}  // namespace

MeanDilatationPatches makeMeanDilatationPatches(const TetMesh& mesh, int patchTets) {
  if (patchTets < 1)
    throw InputError(
        fmt::format("mean dilatation: {} tets per patch; expected at least 1", patchTets));
  const Eigen::Index nt = mesh.numTets();
  std::vector<int> patchOf(nt, -1);
  std::vector<std::vector<int>> tets;
  const auto nb = patchTets > 1 ? faceNeighbours(mesh) : std::vector<std::array<int, 4>>(nt);
  for (Eigen::Index t0 = 0; t0 < nt; ++t0) {
    if (patchOf[t0] >= 0) continue;
    const int p = static_cast<int>(tets.size());
    std::vector<int> members{static_cast<int>(t0)};
    patchOf[t0] = p;
    std::vector<int> nodes{mesh.T(t0, 0), mesh.T(t0, 1), mesh.T(t0, 2), mesh.T(t0, 3)};
    // Grow by the free face neighbour that adds the fewest new nodes (0 or 1; ties: lowest
    // index): compact patches keep the stiffness pattern, and so the factor's fill, small.
    while (static_cast<int>(members.size()) < patchTets) {
      int best = -1, bestNew = 5;
      for (int t : members)
        for (int n : nb[t]) {
          if (n < 0 || patchOf[n] >= 0 || mesh.regionOf(n) != mesh.regionOf(t0)) continue;
          int added = 0;
          for (int a = 0; a < 4; ++a)
            added += std::find(nodes.begin(), nodes.end(), mesh.T(n, a)) == nodes.end();
          if (added < bestNew || (added == bestNew && n < best)) best = n, bestNew = added;
        }
      if (best < 0) break;
      patchOf[best] = p;
      members.push_back(best);
      for (int a = 0; a < 4; ++a)
        if (std::find(nodes.begin(), nodes.end(), mesh.T(best, a)) == nodes.end())
          nodes.push_back(mesh.T(best, a));
    }
    if (members.size() == 1 && patchTets > 1) {
      int host = -1;
      for (int n : nb[t0])
        if (n >= 0 && patchOf[n] != p && mesh.regionOf(n) == mesh.regionOf(t0)) {
          host = patchOf[n];
          break;
        }
      if (host >= 0) {
        patchOf[t0] = host;
        tets[host].push_back(static_cast<int>(t0));
        continue;
      }
    }
    tets.push_back(std::move(members));
  }

  MeanDilatationPatches out;
  out.tets = std::move(tets);
  out.nodes.resize(out.tets.size());
  out.local.resize(out.tets.size());
  for (size_t p = 0; p < out.tets.size(); ++p) {
    auto& nodes = out.nodes[p];
    for (int t : out.tets[p])
      for (int a = 0; a < 4; ++a) nodes.push_back(mesh.T(t, a));
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    for (int t : out.tets[p])
      for (int a = 0; a < 4; ++a)
        out.local[p].push_back(static_cast<int>(
            std::lower_bound(nodes.begin(), nodes.end(), mesh.T(t, a)) - nodes.begin()));
  }
  return out;
}

}  // namespace bcassim
