// .eseg reading: the edge numbering must match the annotation tool's (faces in file order), or
// the labels land on the wrong edges without any error, hence the strict count check.
#include "bcassim/ligaments/EsegLabels.h"

#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <unordered_map>

#include "bcassim/Error.h"

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

namespace {

bool isBlank(const std::string& s) { return s.find_first_not_of(" \t\r") == std::string::npos; }

}  // namespace

LabelledEdges readEseg(const std::string& path, const TriMesh& surface) {
  LabelledEdges out;
  out.edges = esegEdgeOrder(surface);
  const size_t expected = out.edges.size();
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file");
  std::string line;
  int lineNumber = 0;
  int firstBlankAfterLabels = 0;  // trailing blank lines are accepted, blank lines inside are not
  while (std::getline(in, line)) {
    ++lineNumber;
    if (isBlank(line)) {
      if (!firstBlankAfterLabels) firstBlankAfterLabels = lineNumber;
      continue;
    }
    if (firstBlankAfterLabels) {
      throw InputError(
          fmt::format("{}:{}: blank line between edge labels", path, firstBlankAfterLabels));
    }
    const size_t begin = line.find_first_not_of(" \t");
    const size_t end = line.find_last_not_of(" \t\r") + 1;
    int value = 0;
    const auto [ptr, ec] = std::from_chars(line.data() + begin, line.data() + end, value);
    if (ec != std::errc() || ptr != line.data() + end) {
      throw InputError(fmt::format("{}:{}: expected an integer edge label, got '{}'", path,
                                   lineNumber,
                                   line.substr(begin, std::min<size_t>(end - begin, 40))));
    }
    if (out.labels.size() == expected) {
      throw InputError(
          fmt::format("{}:{}: expected {} edge labels (one per surface edge), the file has more",
                      path, lineNumber, expected));
    }
    out.labels.push_back(value);
  }
  if (out.labels.size() != expected) {
    throw InputError(
        fmt::format("{}:{}: expected {} edge labels (one per surface edge), the file ends after {}",
                    path, out.labels.size() + 1, expected, out.labels.size()));
  }
  return out;
}

}  // namespace bcassim
