// A ParaView time series written incrementally: one .vtu per frame plus a .pvd index rewritten
// after every frame, so the series stays valid if the run is killed. Times in seconds.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "bcassim/io/FieldSet.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// One <DataSet> of a .pvd written by PvdSeries: time (s), part index (0: the mesh), file name
// relative to the .pvd.
struct PvdEntry {
  double time = 0;
  int part = 0;
  std::string file;
};

// The entries of a .pvd written by PvdSeries, in file order. Throws InputError if it cannot be
// opened.
std::vector<PvdEntry> readPvdIndex(const std::string& pvdPath);

class PvdSeries {
 public:
  // Files go to `directory` (created if missing) as <baseName>.pvd and <baseName>_000042.vtu.
  // Throws InputError when the directory cannot be created.
  PvdSeries(const std::string& directory, const std::string& baseName);

  // Writes frame <baseName>_<index>.vtu with the mesh at `positions` (3N node-major, m; empty
  // means rest positions) and `fields`, then rewrites the .pvd. Returns the frame index.
  int addFrame(double time, const TetMesh& mesh, const Eigen::VectorXd& positions,
               const FieldSet& fields = FieldSet());

  // Adds to the latest frame another part named `part` (letters, digits, '_', '-'), written as
  // <baseName>_<part>_<index>.vtp: a point cloud (e.g. markers) or line segments (e.g. springs).
  // ParaView shows each part as a block of the same time step.
  void addPoints(const std::string& part, const Eigen::MatrixX3d& points,
                 const FieldSet& fields = FieldSet());
  void addPolyLines(const std::string& part, const Eigen::MatrixX3d& points,
                    const Eigen::MatrixX2i& segments, const FieldSet& fields = FieldSet());

  // Continues the series already in `directory`: keeps the first `frames` frames listed in its
  // .pvd (with their parts) and drops later ones, whose files the next frames overwrite. Throws
  // InputError if the .pvd cannot be read or lists fewer frames.
  static PvdSeries resume(const std::string& directory, const std::string& baseName, int frames);

  int numFrames() const { return numFrames_; }
  std::string pvdPath() const;

 private:
  using Entry = PvdEntry;

  std::string partFile(const std::string& part, const char* extension, int* partIndex);
  void rewriteIndex() const;

  std::string directory_;
  std::string baseName_;
  std::vector<std::string> parts_;  // part names; index 0 is the mesh
  std::vector<Entry> entries_;
  double lastTime_ = 0.0;
  int numFrames_ = 0;
};

}  // namespace bcassim
