// Sends one step's predictions to every client of the server (hidden points with their 95 %
// radius as POINT `bcassim_hidden`, the deformed surface as POLYDATA `bcassim_surface`) and logs
// the frame's latency, from its arrival to its answer sent, in latency.csv.
#pragma once
#include <Eigen/Core>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "bcassim/mesh/TetMesh.h"
#include "bcassim/run/AssimilationStream.h"
#include "bcassim/stream/IgtlServer.h"

namespace bcassim {

// The frame a prediction answers: its stamp, sender and arrival.
struct AnsweredFrame {
  long step = 0;
  double stamp = 0.0;  // s
  int client = 0;
  std::chrono::steady_clock::time_point arrival;
};

class FramePublisher {
 public:
  // Opens dir/latency.csv. With sendSurface the mesh's boundary is sent every frame.
  FramePublisher(IgtlServer& server, const TetMesh& mesh, bool sendSurface,
                 const std::filesystem::path& dir);

  // Sends the predictions of step `step` stamped `stamp`; with `frame` (a received frame, not a
  // step without one) its latency is logged. lagFrames: how many frames the analysis behind it
  // is older than the freshest possible (0 in the synchronous mode).
  void publish(long step, double time, double stamp,
               const std::vector<HiddenPointPrediction>& hidden,
               const Eigen::VectorXd& nodePositions, const std::optional<AnsweredFrame>& frame,
               long lagFrames = 0);

  const std::vector<double>& latencyMs() const { return latencyMs_; }

 private:
  IgtlServer& server_;
  bool sendSurface_;
  std::vector<int> surfaceNodes_;
  Eigen::MatrixX3i surfaceFaces_;
  std::filesystem::path path_;
  std::ofstream out_;
  std::vector<double> latencyMs_;
};

}  // namespace bcassim
