// Labelled-edge graph -> ordered polyline. Annotations are drawn by hand, so the labelled edges
// may branch (a stray edge beside the line) or break (an unlabelled edge inside it).
#include "bcassim/ligaments/AttachmentCurve.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <queue>

#include "bcassim/Error.h"

namespace bcassim {
namespace {

using Graph = std::map<int, std::vector<std::pair<int, double>>>;  // vertex -> (neighbour, length)

// Shortest-path distances and predecessors from `source` within its component.
void dijkstra(const Graph& graph, int source, std::map<int, double>& dist,
              std::map<int, int>& prev) {
  dist.clear();
  prev.clear();
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  dist[source] = 0;
  queue.push({0, source});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    for (const auto& [w, len] : graph.at(v)) {
      auto it = dist.find(w);
      if (it == dist.end() || d + len < it->second) {
        dist[w] = d + len;
        prev[w] = v;
        queue.push({d + len, w});
      }
    }
  }
}

// Farthest vertex (ties: smallest id, for determinism).
int farthest(const std::map<int, double>& dist) {
  int best = dist.begin()->first;
  for (const auto& [v, d] : dist) {
    if (d > dist.at(best)) best = v;
  }
  return best;
}

struct Piece {
  std::vector<int> path;
  double length = 0;
  int size = 0;  // vertices in the component
};

double pathLength(const std::vector<int>& path, const Eigen::MatrixX3d& V) {
  double length = 0;
  for (size_t i = 1; i < path.size(); ++i) length += (V.row(path[i]) - V.row(path[i - 1])).norm();
  return length;
}

}  // namespace

AttachmentCurve extractAttachmentCurve(const TriMesh& surface, const LabelledEdges& edges,
                                       int label, const std::string& source, double maxGap) {
  if (edges.edges.size() != edges.labels.size()) {
    throw InputError(
        fmt::format("{}: {} edges but {} labels", source, edges.edges.size(), edges.labels.size()));
  }
  const Eigen::MatrixX3d& V = surface.V;
  Graph graph;
  for (size_t e = 0; e < edges.edges.size(); ++e) {
    if (edges.labels[e] != label) continue;
    const auto [a, b] = edges.edges[e];
    if (a < 0 || b < 0 || a >= V.rows() || b >= V.rows()) {
      throw InputError(fmt::format("{}: edge {} refers to a vertex out of range", source, e));
    }
    const double len = (V.row(a) - V.row(b)).norm();
    graph[a].push_back({b, len});
    graph[b].push_back({a, len});
  }
  if (graph.empty()) throw InputError(fmt::format("{}: no edge carries label {}", source, label));

  // Each component's longest path by two sweeps: farthest from any vertex, then farthest from it.
  std::vector<Piece> pieces;
  std::map<int, bool> done;
  std::map<int, double> dist;
  std::map<int, int> prev;
  for (const auto& [start, unused] : graph) {
    if (done[start]) continue;
    dijkstra(graph, start, dist, prev);
    for (const auto& [v, d] : dist) done[v] = true;
    Piece piece;
    piece.size = static_cast<int>(dist.size());
    const int a = farthest(dist);
    dijkstra(graph, a, dist, prev);
    int v = farthest(dist);
    piece.path.push_back(v);
    while (v != a) {
      v = prev.at(v);
      piece.path.push_back(v);
    }
    piece.length = pathLength(piece.path, V);
    pieces.push_back(std::move(piece));
  }
  std::stable_sort(pieces.begin(), pieces.end(),
                   [](const Piece& x, const Piece& y) { return x.length > y.length; });

  AttachmentCurve curve;
  curve.components = static_cast<int>(pieces.size());
  std::vector<int> path = pieces[0].path;
  curve.droppedVertices = pieces[0].size - static_cast<int>(pieces[0].path.size());
  std::vector<bool> used(pieces.size(), false);
  used[0] = true;
  for (size_t round = 1; round < pieces.size(); ++round) {
    // The unused piece whose endpoint is nearest to either end of the chain.
    double best = std::numeric_limits<double>::infinity();
    size_t bestPiece = 0;
    bool atFront = false, reversePiece = false;
    for (size_t p = 1; p < pieces.size(); ++p) {
      if (used[p]) continue;
      const std::vector<int>& q = pieces[p].path;
      const std::array<std::array<int, 2>, 4> pairs = {{{path.back(), q.front()},
                                                        {path.back(), q.back()},
                                                        {path.front(), q.back()},
                                                        {path.front(), q.front()}}};
      for (int k = 0; k < 4; ++k) {
        const double d = (V.row(pairs[k][0]) - V.row(pairs[k][1])).norm();
        if (d < best) {
          best = d;
          bestPiece = p;
          atFront = k >= 2;
          reversePiece = (k == 1 || k == 3);
        }
      }
    }
    if (best > maxGap) break;
    used[bestPiece] = true;
    std::vector<int> q = pieces[bestPiece].path;
    if (reversePiece) std::reverse(q.begin(), q.end());
    if (atFront) {
      path.insert(path.begin(), q.begin(), q.end());
    } else {
      path.insert(path.end(), q.begin(), q.end());
    }
    curve.gapLength += best;
    curve.droppedVertices += pieces[bestPiece].size - static_cast<int>(q.size());
    ++curve.joined;
  }
  for (size_t p = 0; p < pieces.size(); ++p) {
    if (!used[p]) curve.droppedVertices += pieces[p].size;
  }
  if (path.front() > path.back()) std::reverse(path.begin(), path.end());
  curve.vertices = path;
  curve.points.resize(static_cast<Eigen::Index>(path.size()), 3);
  for (size_t i = 0; i < path.size(); ++i) curve.points.row(i) = V.row(path[i]);
  curve.length = pathLength(path, V);
  return curve;
}

}  // namespace bcassim
