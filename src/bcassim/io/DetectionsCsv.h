// Raw detections of unlabelled points as CSV, one row per detection: time,x,y,z (s, m), the rows
// of one camera frame together, no ids: what a camera pipeline gives and `bcassim track` reads.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace bcassim {

// One camera frame: its time and what was detected in it, in no particular order.
struct TimedPoints {
  double time = 0.0;        // s
  Eigen::MatrixX3d points;  // #detections by 3, m
};

// Consecutive rows with the same time form one frame, in file order: a time out of order starts a
// frame of its own and is left to the tracker to report, not refused here. The header line
// (time,x,y,z) is optional; blank lines and lines starting with '#' are skipped. A coordinate or
// a time may be nan or inf (kept as read: the tracker drops and reports such a detection or
// frame); a row whose three coordinates are empty ("0.5,,,") is a frame without detections.
// Throws InputError naming the file and line for a row without 4 fields, a field that is not a
// number, a header other than time,x,y,z, or a file without rows, e.g. "det.csv:7: field y is
// not a number ('a')".
std::vector<TimedPoints> readDetectionsCsv(const std::string& path);

// Writes `frames` in that order with the header time,x,y,z (numbers at round-trip precision; a
// frame without detections as "time,,,"). Creates the parent folder. Throws InputError when the
// file cannot be written.
void writeDetectionsCsv(const std::string& path, const std::vector<TimedPoints>& frames);

}  // namespace bcassim
