// An element loop's forces summed in a fixed number of chunks of its elements, each into a buffer
// of its own, the buffers then added in chunk order: a force assembly spread over threads whose
// result does not depend on how many there are (for a solve that has the cores to itself).
#pragma once
#include <Eigen/Core>
#include <functional>
#include <memory>

namespace bcassim {

class ChunkedForces {
 public:
  static constexpr int kChunks = 4;

  explicit ChunkedForces(int threads);
  ~ChunkedForces();
  ChunkedForces(const ChunkedForces&) = delete;
  ChunkedForces& operator=(const ChunkedForces&) = delete;

  int threads() const;
  // Zeroes the chunks' buffers to `size` entries.
  void begin(Eigen::Index size);
  // Runs work(chunk, first, last, buffer) for the kChunks chunks [first, last) of [0, count) on
  // the threads, each with the chunk's own buffer.
  void forEachChunk(
      Eigen::Index count,
      const std::function<void(int, Eigen::Index, Eigen::Index, Eigen::VectorXd&)>& work);
  // f += the buffers, in chunk order.
  void addTo(Eigen::VectorXd& f) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bcassim
