// Reading a CSV table of numbers with an optional header line, e.g. control-point trajectories
// (time,x,y,z rows in s and m). Every parse error names the file, the line and the field.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace bcassim {

struct CsvTable {
  std::vector<std::string> header;  // column names; empty when the file has no header line
  Eigen::MatrixXd rows;             // one row per data line
  std::vector<int> lines;           // source line number of each row, for callers' messages

  // Index of the column named `name`, or -1.
  int column(const std::string& name) const;
};

// A first line without any number is the header. Blank lines and lines starting with '#'
// are skipped; fields are comma-separated and trimmed. Every row must have as many fields as the
// first and every value must be finite. Throws InputError, e.g.
// "traj.csv:17: field z is not a finite number ('nan')" or "traj.csv:3: expected 4 fields
// (time,x,y,z), got 3".
CsvTable readCsvTable(const std::string& path);

}  // namespace bcassim
