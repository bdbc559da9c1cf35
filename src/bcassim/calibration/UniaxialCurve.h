// A measured uniaxial stress-strain curve of a tissue sample (e.g. peritoneum, thesis §2.3.4,
// §4.4), read from CSV: stretch or engineering strain, nominal or Cauchy stress in Pa, as the
// header says. Stored as stretch and nominal stress.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace bcassim {

struct UniaxialCurve {
  Eigen::VectorXd stretch;        // lambda = l / L > 0, -
  Eigen::VectorXd nominalStress;  // force per reference area, Pa
  std::vector<int> lines;         // the file line of each point, for messages
};

// The header names the two columns (case-insensitive, other columns ignored):
//   stretch | strain (engineering, lambda - 1)
//   nominal_stress_Pa (alias engineering_stress_Pa) | cauchy_stress_Pa (alias true_stress_Pa)
// Throws InputError with one line naming the file and line: a stress column in kPa or MPa
// ("expected Pa (SI units)"), a missing column, a stretch <= 0 (a strain <= -1), fewer than 2
// points, or stresses all below 1 Pa in magnitude (a curve in MPa or kPa under a Pa header).
UniaxialCurve readUniaxialCurve(const std::string& path);

}  // namespace bcassim
