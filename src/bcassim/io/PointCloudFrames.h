// Reading a point cloud frame by frame (observations.point_cloud): one file per frame (a folder,
// or a pattern with '*'), or one CSV with a frame or time column. Points that are not finite are
// dropped with a notice instead of failing the run; anything else malformed is an InputError.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace bcassim {

// One frame as read: its points (#P by 3, m; may be empty), its key (the file's rank, the CSV's
// frame number or time) and a name for notices ("pc07.txt", "cloud.csv frame 7").
struct CloudFrame {
  Eigen::MatrixX3d points;
  double key = 0.0;
  std::string name;
};

// The frame files of `folderOrPattern`: every .txt, .csv, .npy and .ply file of a folder, or the
// files whose name matches a pattern with '*' in its last component ("pointclouds/pc*.txt"), in
// natural name order (pc2 before pc10). Throws InputError when nothing matches.
std::vector<std::string> cloudFrameFiles(const std::string& folderOrPattern);

// The points of one frame file: .txt (x y z per line, '#' comments), .csv (x,y,z columns named
// in a header, or exactly 3 columns), .npy ((N, 3) numbers) or .ply (the vertices, io/PlyReader). A
// point with a coordinate that is not finite is dropped and one line per file is added to `notices`
// ("pc07.txt: 2 points not finite (line 12 first), dropped"). Throws InputError naming file and
// line for anything else.
Eigen::MatrixX3d readCloudFile(const std::string& path, std::vector<std::string>& notices);

// Frames of one CSV with columns frame (or time), x, y, z named in a header: rows of equal key
// form a frame, in order of first appearance. Non-finite points are dropped with a notice per
// frame; a key smaller than one before it is kept (frames go to the step of their own key) with
// a notice "cloud.csv:120: time 0.1 s comes after 0.2 s (out of order)". `byTime` tells which
// column was found (time: true).
std::vector<CloudFrame> readCloudCsv(const std::string& path, bool& byTime,
                                     std::vector<std::string>& notices);

}  // namespace bcassim
