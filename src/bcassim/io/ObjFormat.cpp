#include "bcassim/io/ObjFormat.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {

TriMesh readObj(const std::string& path) {
  io::TextLines in(path);
  std::vector<double> coords;
  std::vector<long long> corners;  // 0-based, resolved once all vertices are known
  std::vector<int> faceLines;      // source line per triangle, for messages
  std::vector<long long> polygon;
  static constexpr char kAxes[] = {'x', 'y', 'z'};
  while (in.next()) {
    const auto f = io::splitBlanks(in.line());
    if (f.empty() || f[0][0] == '#') continue;
    if (f[0] == "v") {
      if (f.size() != 4 && f.size() != 5)
        in.fail(fmt::format("expected 3 coordinates after 'v', got {}", f.size() - 1));
      for (int k = 0; k < 3; ++k) {
        double x = 0;
        if (!io::parseDouble(f[k + 1], x))
          in.fail(fmt::format("expected a number for vertex coordinate {}, got '{}'", kAxes[k],
                              io::excerpt(f[k + 1])));
        if (!std::isfinite(x))
          in.fail(fmt::format("vertex coordinate {} is not a finite number ('{}')", kAxes[k],
                              io::excerpt(f[k + 1])));
        coords.push_back(x);
      }
    } else if (f[0] == "f") {
      if (f.size() < 4)
        in.fail(fmt::format("expected at least 3 vertices in a face, got {}", f.size() - 1));
      polygon.clear();
      const long long defined = static_cast<long long>(coords.size() / 3);
      for (size_t k = 1; k < f.size(); ++k) {
        const std::string_view vertex = f[k].substr(0, f[k].find('/'));
        long long index = 0;
        if (!io::parseInt(vertex, index))
          in.fail(fmt::format("expected a vertex index in face vertex '{}'", io::excerpt(f[k])));
        if (index == 0) in.fail("face vertex index 0 is invalid; OBJ indices start at 1");
        if (index < 0) {
          if (-index > defined)
            in.fail(
                fmt::format("relative face vertex index {} goes before the first vertex ({} "
                            "defined so far)",
                            index, defined));
          polygon.push_back(defined + index);
        } else {
          polygon.push_back(index - 1);
        }
      }
      for (size_t k = 1; k + 1 < polygon.size(); ++k) {
        corners.insert(corners.end(), {polygon[0], polygon[k], polygon[k + 1]});
        faceLines.push_back(in.lineNumber());
      }
    }
  }
  const long long numVertices = static_cast<long long>(coords.size() / 3);
  if (corners.empty())
    throw InputError(fmt::format("{}: no faces; expected 'f' lines of a triangle surface", path));
  TriMesh mesh;
  mesh.V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      coords.data(), numVertices, 3);
  mesh.F.resize(static_cast<Eigen::Index>(faceLines.size()), 3);
  for (Eigen::Index t = 0; t < mesh.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const long long v = corners[3 * t + k];
      if (v >= numVertices)
        throw InputError(
            fmt::format("{}:{}: face refers to vertex {}, but the file defines {} "
                        "vertices",
                        path, faceLines[t], v + 1, numVertices));
      mesh.F(t, k) = static_cast<int>(v);
    }
  return mesh;
}

void writeObj(const std::string& path, const TriMesh& mesh) {
  io::createParentDirectory(path);
  std::ofstream out(path, std::ios::binary);
  if (!out) io::throwWriteError(path);
  fmt::memory_buffer buffer;
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    fmt::format_to(std::back_inserter(buffer), "v {} {} {}\n", mesh.V(i, 0), mesh.V(i, 1),
                   mesh.V(i, 2));
  for (Eigen::Index t = 0; t < mesh.F.rows(); ++t)
    fmt::format_to(std::back_inserter(buffer), "f {} {} {}\n", mesh.F(t, 0) + 1, mesh.F(t, 1) + 1,
                   mesh.F(t, 2) + 1);
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  out.close();
  if (!out) io::throwWriteError(path);
}

}  // namespace bcassim
