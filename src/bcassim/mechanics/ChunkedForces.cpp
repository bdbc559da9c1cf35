#include "bcassim/mechanics/ChunkedForces.h"

#include <tbb/task_arena.h>

#include <array>
#include <stdexcept>

#include "bcassim/mechanics/ArenaLoop.h"

namespace bcassim {

struct ChunkedForces::Impl {
  int threads;
  tbb::task_arena arena;
  std::array<Eigen::VectorXd, kChunks> buffers;
  explicit Impl(int n) : threads(n), arena(n) {}
};

ChunkedForces::ChunkedForces(int threads) {
  if (threads < 1) throw std::invalid_argument("ChunkedForces: threads must be >= 1");
  impl_ = std::make_unique<Impl>(threads);
}

ChunkedForces::~ChunkedForces() = default;

int ChunkedForces::threads() const { return impl_->threads; }

void ChunkedForces::begin(Eigen::Index size) {
  for (Eigen::VectorXd& b : impl_->buffers) b.setZero(size);
}

void ChunkedForces::forEachChunk(
    Eigen::Index count,
    const std::function<void(int, Eigen::Index, Eigen::Index, Eigen::VectorXd&)>& work) {
  const auto run = [&](int c) {
    work(c, count * c / kChunks, count * (c + 1) / kChunks, impl_->buffers[static_cast<size_t>(c)]);
  };
  forEachOnArena(impl_->arena, kChunks, run);
}

void ChunkedForces::addTo(Eigen::VectorXd& f) const {
  for (const Eigen::VectorXd& b : impl_->buffers) f += b;
}

}  // namespace bcassim
