#include "bcassim/io/PointCsvWriter.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"

namespace bcassim {
namespace {

std::ofstream openCsv(const std::string& path) {
  io::createParentDirectory(path);
  std::ofstream out(path);
  if (!out) io::throwWriteError(path);
  return out;
}

void finish(std::ofstream& out, const std::string& path) {
  out.flush();
  if (!out) io::throwWriteError(path);
}

}  // namespace

void writePointsCsv(const std::string& path, const Eigen::MatrixX3d& points,
                    const std::vector<NamedColumn>& extra) {
  for (const NamedColumn& c : extra)
    if (c.values.size() != points.rows())
      throw std::invalid_argument(
          fmt::format("writePointsCsv: column {} has {} values for {} points", c.name,
                      c.values.size(), points.rows()));
  std::ofstream out = openCsv(path);
  out << "x,y,z";
  for (const NamedColumn& c : extra) out << ',' << c.name;
  out << '\n';
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    out << fmt::format("{:.17g},{:.17g},{:.17g}", points(i, 0), points(i, 1), points(i, 2));
    for (const NamedColumn& c : extra) out << fmt::format(",{:.17g}", c.values(i));
    out << '\n';
  }
  finish(out, path);
}

void writePointSetsCsv(const std::string& path, const std::string& setColumn,
                       const std::vector<Eigen::MatrixX3d>& sets) {
  std::ofstream out = openCsv(path);
  out << setColumn << ",x,y,z\n";
  for (size_t s = 0; s < sets.size(); ++s)
    for (Eigen::Index i = 0; i < sets[s].rows(); ++i)
      out << fmt::format("{},{:.17g},{:.17g},{:.17g}\n", s, sets[s](i, 0), sets[s](i, 1),
                         sets[s](i, 2));
  finish(out, path);
}

}  // namespace bcassim
