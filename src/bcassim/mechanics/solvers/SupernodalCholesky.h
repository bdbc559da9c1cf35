// The numeric phase of a supernodal Cholesky factorisation on several threads, written into a
// CHOLMOD supernodal factor's own layout, so that CHOLMOD's solves and CholeskyFactor's sweeps read
// it unchanged. Left-looking with BLAS-3 per supernode, as CHOLMOD's; the groups of whole subtrees
// of the elimination tree run concurrently, the top supernodes above them after (their updates in
// pieces, the widest factorised in panels, both on the threads).
#pragma once
#include <tbb/task_arena.h>

#include <array>
#include <cstdint>
#include <vector>

#include "bcassim/Types.h"

struct cholmod_factor_struct;

namespace bcassim {

class SupernodalCholesky {
 public:
  // For matrices with A's pattern (both triangles stored, the lower read) under L's analysis
  // (supernodal, its rows sorted in each supernode, as CHOLMOD makes them). `groups` hold whole
  // subtrees of L's supernodal tree, each ascending; `top` (ascending) every other supernode.
  SupernodalCholesky(const cholmod_factor_struct& L, const SparseMatrix& A,
                     const std::vector<std::vector<int>>& groups, const std::vector<int>& top);

  // Whether A has the pattern this was made for (the same row indices in every column).
  bool matches(const SparseMatrix& A) const;

  // L's values for A into Lx (L's xsize entries): the groups on the arena's threads, then the
  // top, each supernode's pieces on them. Every supernode sums its updates in one fixed order, so
  // any number of threads gives the same bits. Returns -1, or the first column (in L's ordering)
  // whose pivot is not positive; Lx is then not a factor.
  std::int64_t factorize(const SparseMatrix& A, double* Lx, tbb::task_arena& arena) const;

 private:
  struct Scratch {
    std::vector<int> map;        // a row's place in the supernode at hand
    std::vector<double> update;  // one descendant's update
  };
  struct Update {
    int from;    // the descendant supernode
    int offset;  // the position, in its rows, of its first row among this supernode's columns
    int count;   // how many of its rows are this supernode's columns
  };
  static constexpr int kTopChunks = 2;        // a top supernode's columns in this many pieces
  static constexpr int kChunkedColumns = 32;  // when it has at least this many
  static constexpr int kPanelColumns = 128;   // finishInPanels' panels, for top supernodes as wide
  void assemble(int s, const SparseMatrix& A, double* Lx, std::vector<int>& map) const;
  void subtractUpdates(int s, int c0, int c1, double* Lx, const std::vector<int>& map,
                       std::vector<double>& update) const;
  std::int64_t finish(int s, double* Lx) const;
  std::int64_t finishInPanels(int s, double* Lx, tbb::task_arena& arena) const;
  static std::array<int, kTopChunks + 1> balancedCut(int from, int to, int rows);

  std::vector<int> super_, pi_, rows_;
  std::vector<std::int64_t> px_;
  std::vector<int> outer_, inner_;         // A's pattern, for matches()
  std::vector<std::int64_t> entryStart_;   // per supernode, into the two below
  std::vector<int> entryOfA_;              // A's stored entry (lower triangle)
  std::vector<std::int64_t> entryInL_;     // where it goes in Lx
  std::vector<std::int64_t> updateStart_;  // per supernode, into updates_
  std::vector<Update> updates_;            // ascending descendants
  std::vector<std::vector<int>> groups_;
  std::vector<int> top_;
  std::int64_t largestUpdate_ = 0;
  int n_ = 0;
};

}  // namespace bcassim
