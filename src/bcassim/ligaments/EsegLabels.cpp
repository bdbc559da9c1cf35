// .eseg reading: the edge numbering must match the annotation tool's (faces in file order), or
// the labels land on the wrong edges without any error, hence the strict count check.
#include "bcassim/ligaments/EsegLabels.h"

#include <fmt/format.h>

#include <climits>
#include <unordered_map>

#include "bcassim/Error.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {

std::vector<std::array<int, 2>> esegEdgeOrder(const TriMesh& surface) {
  std::vector<std::array<int, 2>> edges;
  std::unordered_map<long long, int> seen;
  const long long n = surface.V.rows();
  edges.reserve(static_cast<size_t>(surface.F.rows()) * 3 / 2 + 3);
  for (Eigen::Index f = 0; f < surface.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = surface.F(f, k), b = surface.F(f, (k + 1) % 3);
      const long long key = std::min(a, b) * n + std::max(a, b);
      if (seen.emplace(key, static_cast<int>(edges.size())).second) edges.push_back({a, b});
    }
  }
  return edges;
}

LabelledEdges readEseg(const std::string& path, const TriMesh& surface) {
  LabelledEdges out;
  out.edges = esegEdgeOrder(surface);
  const size_t expected = out.edges.size();
  io::TextLines in(path);
  int firstBlankAfterLabels = 0;  // trailing blank lines are accepted, blank lines inside are not
  while (in.next()) {
    const std::string_view label = io::trim(in.line());
    if (label.empty()) {
      if (!firstBlankAfterLabels) firstBlankAfterLabels = in.lineNumber();
      continue;
    }
    if (firstBlankAfterLabels)
      throw InputError(
          fmt::format("{}:{}: blank line between edge labels", path, firstBlankAfterLabels));
    long long value = 0;
    if (!io::parseInt(label, value) || value < INT_MIN || value > INT_MAX)
      in.fail(fmt::format("expected an integer edge label, got '{}'", io::excerpt(label)));
    if (out.labels.size() == expected)
      in.fail(fmt::format("expected {} edge labels (one per surface edge), the file has more",
                          expected));
    out.labels.push_back(static_cast<int>(value));
  }
  if (out.labels.size() != expected) {
    throw InputError(
        fmt::format("{}:{}: expected {} edge labels (one per surface edge), the file ends after {}",
                    path, out.labels.size() + 1, expected, out.labels.size()));
  }
  return out;
}

Eigen::MatrixX2i edgesLabelled(const LabelledEdges& e, int label) {
  Eigen::Index count = 0;
  for (int l : e.labels) count += l == label ? 1 : 0;
  Eigen::MatrixX2i out(count, 2);
  Eigen::Index row = 0;
  for (size_t i = 0; i < e.labels.size() && i < e.edges.size(); ++i) {
    if (e.labels[i] != label) continue;
    out(row, 0) = e.edges[i][0];
    out(row, 1) = e.edges[i][1];
    ++row;
  }
  return out.topRows(row);
}

}  // namespace bcassim
