// Marker tracks as CSV, one row per marker and frame: columns time,marker,x,y,z (s, index, m).
// Written incrementally (flushed every frame) so a killed run leaves a readable file.
#pragma once
#include <Eigen/Core>
#include <fstream>
#include <string>
#include <vector>

#include "bcassim/io/CsvTable.h"  // readCsvTable, for the other CSV inputs read beside tracks

namespace bcassim {

class MarkerTrackWriter {
 public:
  // Creates the parent directory if missing, truncates `path` and writes the header.
  // Throws InputError when the file cannot be written.
  explicit MarkerTrackWriter(const std::string& path);
  // Continues `path` (resumed runs): keeps its header and the rows up to time `until` (s; rows
  // later than until + 1e-9 s are dropped), then appends. Throws InputError if it cannot be read
  // or written.
  MarkerTrackWriter(const std::string& path, double until);

  // Writes one row per marker (row i of `positions` is marker i), skipping rows holding NaN
  // (markers not seen in this frame), and flushes.
  void write(double time, const Eigen::MatrixX3d& positions);

 private:
  std::string path_;
  std::ofstream out_;
};

struct MarkerTracks {
  std::vector<double> times;             // s, increasing
  std::vector<Eigen::MatrixX3d> frames;  // numMarkers rows each, m; NaN rows for missing markers
  int numMarkers = 0;                    // 1 + largest marker index in the file
};

// Rows with equal time form one frame; times must be non-decreasing and a marker appears at
// most once per frame. The header line is optional. Throws InputError naming the line, e.g.
// "tracks.csv:17: field z is not a finite number ('nan')".
MarkerTracks readMarkerTracks(const std::string& path);

}  // namespace bcassim
