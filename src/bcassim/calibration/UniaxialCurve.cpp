#include "bcassim/calibration/UniaxialCurve.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTable.h"

namespace bcassim {

namespace {
std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

int findColumn(const std::vector<std::string>& header, std::initializer_list<const char*> names) {
  for (size_t i = 0; i < header.size(); ++i)
    for (const char* n : names)
      if (lower(header[i]) == n) return static_cast<int>(i);
  return -1;
}
}  // namespace

UniaxialCurve readUniaxialCurve(const std::string& path) {
  const CsvTable table = readCsvTable(path);
  if (table.header.empty())
    throw InputError(fmt::format(
        "{}:1: expected a header naming the columns, e.g. strain,nominal_stress_Pa", path));
  for (const std::string& name : table.header) {
    const std::string n = lower(name);
    if (n.find("stress") != std::string::npos &&
        (n.ends_with("_kpa") || n.ends_with("_mpa") || n.ends_with("_gpa")))
      throw InputError(fmt::format(
          "{}:1: column {}: stress in {}; expected Pa (SI units), e.g. nominal_stress_Pa", path,
          name, name.substr(name.rfind('_') + 1)));
  }
  const int stretchCol = findColumn(table.header, {"stretch"});
  const int strainCol = findColumn(table.header, {"strain"});
  const int nominalCol = findColumn(table.header, {"nominal_stress_pa", "engineering_stress_pa"});
  const int cauchyCol = findColumn(table.header, {"cauchy_stress_pa", "true_stress_pa"});
  if ((stretchCol < 0) == (strainCol < 0))
    throw InputError(fmt::format("{}:1: expected one column stretch or strain", path));
  if ((nominalCol < 0) == (cauchyCol < 0))
    throw InputError(fmt::format(
        "{}:1: expected one column nominal_stress_Pa or cauchy_stress_Pa (SI units)", path));
  const Eigen::Index n = table.rows.rows();
  if (n < 2)
    throw InputError(fmt::format("{}: {} data line(s); expected at least 2 points", path, n));

  UniaxialCurve curve;
  curve.stretch.resize(n);
  curve.nominalStress.resize(n);
  curve.lines = table.lines;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double l = stretchCol >= 0 ? table.rows(i, stretchCol) : 1.0 + table.rows(i, strainCol);
    if (!(l > 0.0))
      throw InputError(
          fmt::format("{}:{}: {} {}: expected a stretch > 0 (a strain > -1)", path, table.lines[i],
                      stretchCol >= 0 ? "stretch" : "strain",
                      stretchCol >= 0 ? table.rows(i, stretchCol) : table.rows(i, strainCol)));
    curve.stretch(i) = l;
    curve.nominalStress(i) =
        nominalCol >= 0 ? table.rows(i, nominalCol) : table.rows(i, cauchyCol) / l;
  }
  if (curve.nominalStress.cwiseAbs().maxCoeff() < 1.0)
    throw InputError(fmt::format(
        "{}: every stress is below 1 Pa in magnitude (largest {:g}): is the curve in kPa or "
        "MPa? expected Pa (SI units)",
        path, curve.nominalStress.cwiseAbs().maxCoeff()));
  return curve;
}

}  // namespace bcassim
