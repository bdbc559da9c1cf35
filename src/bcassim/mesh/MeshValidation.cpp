#include "bcassim/mesh/MeshValidation.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {
namespace {

// "liver.msh:812: element 57" or "liver.vtk: tet 17": where a tet or node is, as the file says.
std::string itemAt(const std::string& source, const std::vector<int>& lines,
                   const std::string& word, const std::vector<long long>& numbers, Eigen::Index i) {
  const std::string where = i < static_cast<Eigen::Index>(lines.size()) && lines[i] > 0
                                ? fmt::format("{}:{}", source, lines[i])
                                : source;
  const long long number = i < static_cast<Eigen::Index>(numbers.size()) ? numbers[i] : i;
  return fmt::format("{}: {} {}", where, word, number);
}

std::string tetAt(const MeshOrigin& o, Eigen::Index t) {
  return itemAt(o.source, o.tetLines, o.tetWord, o.tetNumbers, t);
}
std::string nodeAt(const MeshOrigin& o, Eigen::Index v) {
  return itemAt(o.source, o.nodeLines, o.nodeWord, o.nodeNumbers, v);
}
std::string nodeName(const MeshOrigin& o, int v) {
  const long long number = v < static_cast<int>(o.nodeNumbers.size()) ? o.nodeNumbers[v] : v;
  return fmt::format("{} {}", o.nodeWord, number);
}
std::string tetName(const MeshOrigin& o, Eigen::Index t) {
  const long long number = t < static_cast<Eigen::Index>(o.tetNumbers.size()) ? o.tetNumbers[t] : t;
  const std::string line = t < static_cast<Eigen::Index>(o.tetLines.size()) && o.tetLines[t] > 0
                               ? fmt::format(" (line {})", o.tetLines[t])
                               : std::string();
  return fmt::format("{} {}{}", o.tetWord, number, line);
}

void checkTetNodes(const TetMesh& mesh, const MeshOrigin& origin) {
  // Duplicates by sorting the tets' sorted node lists (faster than hashing on large meshes); the
  // tet reported is the first in file order that repeats an earlier one.
  std::vector<std::pair<std::array<int, 4>, Eigen::Index>> keys(
      static_cast<size_t>(mesh.numTets()));
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    std::array<int, 4>& key = keys[t].first;
    key = {mesh.T(t, 0), mesh.T(t, 1), mesh.T(t, 2), mesh.T(t, 3)};
    std::sort(key.begin(), key.end());
    keys[t].second = t;
    for (int k = 0; k < 3; ++k)
      if (key[k] == key[k + 1])
        throw InputError(fmt::format("{} lists {} twice; expected 4 distinct nodes",
                                     tetAt(origin, t), nodeName(origin, key[k])));
  }
  std::sort(keys.begin(), keys.end());
  Eigen::Index repeat = -1, original = -1;
  for (size_t i = 1; i < keys.size(); ++i)
    if (keys[i].first == keys[i - 1].first && (repeat < 0 || keys[i].second < repeat) &&
        (i < 2 || keys[i - 2].first != keys[i].first)) {
      repeat = keys[i].second;
      original = keys[i - 1].second;
    }
  if (repeat >= 0)
    throw InputError(fmt::format("{} has the same 4 nodes as {}; expected each tetrahedron once",
                                 tetAt(origin, repeat), tetName(origin, original)));
  std::vector<char> used(static_cast<size_t>(mesh.numNodes()), 0);
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t)
    for (int k = 0; k < 4; ++k) used[mesh.T(t, k)] = 1;
  for (Eigen::Index v = 0; v < mesh.numNodes(); ++v)
    if (!used[v])
      throw InputError(
          fmt::format("{} belongs to no tetrahedron; expected every node in one "
                      "(remove unused nodes from the file)",
                      nodeAt(origin, v)));
}

}  // namespace

double signedVolume(const TetMesh& mesh, Eigen::Index t) {
  const Eigen::Vector3d a = mesh.V.row(mesh.T(t, 0));
  const Eigen::Vector3d b = mesh.V.row(mesh.T(t, 1));
  const Eigen::Vector3d c = mesh.V.row(mesh.T(t, 2));
  const Eigen::Vector3d d = mesh.V.row(mesh.T(t, 3));
  return (b - a).cross(c - a).dot(d - a) / 6.0;
}

void validateTetMesh(TetMesh& mesh, const std::string& source) {
  MeshOrigin origin;
  origin.source = source;
  validateTetMesh(mesh, origin);
}

void validateTetMesh(TetMesh& mesh, const MeshOrigin& origin) {
  const std::string& source = origin.source;
  if (mesh.numNodes() == 0) throw InputError(fmt::format("{}: mesh has no nodes", source));
  if (mesh.numTets() == 0) throw InputError(fmt::format("{}: mesh has no tetrahedra", source));
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(mesh.V(i, k)))
        throw InputError(
            fmt::format("{} has a non-finite coordinate ({}); expected a finite number in metres",
                        nodeAt(origin, i), mesh.V(i, k)));
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t)
    for (int k = 0; k < 4; ++k)
      if (mesh.T(t, k) < 0 || mesh.T(t, k) >= mesh.numNodes())
        throw InputError(fmt::format("{} refers to node {}; expected an index in [0, {})",
                                     tetAt(origin, t), mesh.T(t, k), mesh.numNodes()));
  if (mesh.region.size() != 0 && mesh.region.size() != mesh.numTets())
    throw InputError(
        fmt::format("{}: {} region ids for {} tets", source, mesh.region.size(), mesh.numTets()));
  checkTetNodes(mesh, origin);

  // Degeneracy is judged relative to the tet's own size, so units do not matter.
  Eigen::Index positive = 0, firstNegative = -1, firstPositive = -1;
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    const double v = signedVolume(mesh, t);
    double edge = 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        edge = std::max(edge, (mesh.V.row(mesh.T(t, i)) - mesh.V.row(mesh.T(t, j))).norm());
    if (std::abs(v) <= 1e-12 * edge * edge * edge)
      throw InputError(
          fmt::format("{} is degenerate (volume {:.3g} m^3); expected a non-flat tetrahedron",
                      tetAt(origin, t), v));
    if (v > 0) {
      ++positive;
      if (firstPositive < 0) firstPositive = t;
    } else if (firstNegative < 0) {
      firstNegative = t;
    }
  }
  if (positive == mesh.numTets()) return;
  if (positive == 0) {  // consistently reversed convention: flip every tet
    mesh.T.col(2).swap(mesh.T.col(3));
    return;
  }
  // Mixed: the minority orientation is the inverted one.
  const bool negativeIsMinority = positive * 2 >= mesh.numTets();
  const Eigen::Index bad = negativeIsMinority ? firstNegative : firstPositive;
  throw InputError(
      fmt::format("{} is inverted (signed volume {:.3g} m^3); expected the same orientation as the "
                  "other tets",
                  tetAt(origin, bad), signedVolume(mesh, bad)));
}

}  // namespace bcassim
