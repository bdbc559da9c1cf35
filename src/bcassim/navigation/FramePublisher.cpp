#include "bcassim/navigation/FramePublisher.h"

#include <fmt/format.h>

#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/run/OutputFiles.h"
#include "bcassim/stream/IgtlMessages.h"

namespace bcassim {

FramePublisher::FramePublisher(IgtlServer& server, const TetMesh& mesh, bool sendSurface,
                               const std::filesystem::path& dir)
    : server_(server),
      sendSurface_(sendSurface),
      path_(dir / "latency.csv"),
      out_(openForWriting(path_)) {
  out_ << "step,time_s,frame_stamp_s,client,latency_ms,lag_frames,clients\n";
  flushOrThrow(out_, path_);
  if (sendSurface_) {
    const BoundarySurface b = extractBoundary(mesh);
    surfaceNodes_ = b.nodes;
    surfaceFaces_ = toTriMesh(mesh, b).F;
  }
}

void FramePublisher::publish(long step, double time, double stamp,
                             const std::vector<HiddenPointPrediction>& hidden,
                             const Eigen::VectorXd& nodePositions,
                             const std::optional<AnsweredFrame>& frame, long lagFrames) {
  std::vector<NamedPoint> points;
  for (size_t i = 0; i < hidden.size(); ++i)
    points.push_back({fmt::format("hidden_{}", i), hidden[i].position, hidden[i].radius95Total});
  std::string message = encodeIgtlPoints("bcassim_hidden", stamp, "bcassim", points);
  if (sendSurface_) {
    Eigen::MatrixX3d v(static_cast<Eigen::Index>(surfaceNodes_.size()), 3);
    for (size_t i = 0; i < surfaceNodes_.size(); ++i)
      v.row(static_cast<Eigen::Index>(i)) =
          nodePositions.segment<3>(3 * static_cast<Eigen::Index>(surfaceNodes_[i])).transpose();
    message += encodeIgtlSurface("bcassim_surface", stamp, v, surfaceFaces_);
  }
  const int clients = server_.broadcast(message);
  if (!frame) return;
  const double ms =
      1e3 *
      std::chrono::duration<double>(std::chrono::steady_clock::now() - frame->arrival).count();
  latencyMs_.push_back(ms);
  out_ << fmt::format("{},{:.9g},{:.9f},{},{:.3f},{},{}\n", step, time, frame->stamp, frame->client,
                      ms, lagFrames, clients);
  flushOrThrow(out_, path_);
}

}  // namespace bcassim
