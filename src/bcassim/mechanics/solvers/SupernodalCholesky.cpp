#include "bcassim/mechanics/solvers/SupernodalCholesky.h"

#include <cholmod.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <stdexcept>

#include "bcassim/Blas.h"
#include "bcassim/mechanics/ArenaLoop.h"

namespace bcassim {

SupernodalCholesky::SupernodalCholesky(const cholmod_factor& L, const SparseMatrix& A,
                                       const std::vector<std::vector<int>>& groups,
                                       const std::vector<int>& top)
    : groups_(groups), top_(top) {
  if (!L.is_super || L.itype != CHOLMOD_INT || L.Perm == nullptr)
    throw std::invalid_argument(
        "SupernodalCholesky: needs a supernodal factor with int indices and its ordering");
  if (!A.isCompressed() || A.rows() != static_cast<Eigen::Index>(L.n) || A.cols() != A.rows())
    throw std::invalid_argument("SupernodalCholesky: A is not L's size or not compressed");
  n_ = static_cast<int>(L.n);
  const auto nsuper = static_cast<int>(L.nsuper);
  const int* super = static_cast<const int*>(L.super);
  const int* pi = static_cast<const int*>(L.pi);
  const int* px = static_cast<const int*>(L.px);
  const int* rows = static_cast<const int*>(L.s);
  const int* perm = static_cast<const int*>(L.Perm);
  super_.assign(super, super + nsuper + 1);
  pi_.assign(pi, pi + nsuper + 1);
  px_.assign(px, px + nsuper + 1);
  rows_.assign(rows, rows + pi[nsuper]);
  std::vector<int> superOf(static_cast<size_t>(n_)), inverse(static_cast<size_t>(n_));
  for (int s = 0; s < nsuper; ++s) {
    for (int c = super[s]; c < super[s + 1]; ++c) superOf[static_cast<size_t>(c)] = s;
    if (!std::is_sorted(rows + pi[s], rows + pi[s + 1]))
      throw std::invalid_argument("SupernodalCholesky: a supernode's rows are not sorted");
  }
  for (int i = 0; i < n_; ++i) inverse[static_cast<size_t>(perm[i])] = i;

  // A's lower triangle, permuted, entry by entry to its place in L's supernodal blocks.
  outer_.assign(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1);
  inner_.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  std::vector<std::vector<std::pair<int, std::int64_t>>> entries(static_cast<size_t>(nsuper));
  for (int j = 0; j < A.outerSize(); ++j)
    for (int k = A.outerIndexPtr()[j]; k < A.outerIndexPtr()[j + 1]; ++k) {
      const int i = A.innerIndexPtr()[k];
      if (i < j) continue;
      const int a = inverse[static_cast<size_t>(i)], b = inverse[static_cast<size_t>(j)];
      const int row = std::max(a, b), col = std::min(a, b);
      const int s = superOf[static_cast<size_t>(col)];
      const int* begin = rows + pi[s];
      const int* at = std::lower_bound(begin, rows + pi[s + 1], row);
      if (at == rows + pi[s + 1] || *at != row)
        throw std::invalid_argument("SupernodalCholesky: A has an entry outside L's pattern");
      const int nsrow = pi[s + 1] - pi[s];
      entries[static_cast<size_t>(s)].emplace_back(
          k, px[s] + static_cast<std::int64_t>(col - super[s]) * nsrow + (at - begin));
    }
  entryStart_.assign(1, 0);
  for (const auto& list : entries) {
    for (const auto& [k, at] : list) {
      entryOfA_.push_back(k);
      entryInL_.push_back(at);
    }
    entryStart_.push_back(static_cast<std::int64_t>(entryOfA_.size()));
  }

  // Which descendants update each supernode: the runs of a supernode's rows below its own columns
  // that fall in another supernode's columns, in ascending order of descendant.
  std::vector<std::vector<Update>> into(static_cast<size_t>(nsuper));
  for (int d = 0; d < nsuper; ++d) {
    const int nscol = super[d + 1] - super[d], nsrow = pi[d + 1] - pi[d];
    for (int r = nscol; r < nsrow;) {
      const int s = superOf[static_cast<size_t>(rows[pi[d] + r])];
      int count = 0;
      while (r + count < nsrow && rows[pi[d] + r + count] < super[s + 1]) ++count;
      into[static_cast<size_t>(s)].push_back({d, r, count});
      largestUpdate_ = std::max(largestUpdate_, static_cast<std::int64_t>(nsrow - r) * count);
      r += count;
    }
  }
  updateStart_.assign(1, 0);
  for (const auto& list : into) {
    updates_.insert(updates_.end(), list.begin(), list.end());
    updateStart_.push_back(static_cast<std::int64_t>(updates_.size()));
  }
}

bool SupernodalCholesky::matches(const SparseMatrix& A) const {
  return A.rows() == n_ && A.cols() == n_ && A.isCompressed() &&
         static_cast<size_t>(A.nonZeros()) == inner_.size() &&
         std::equal(outer_.begin(), outer_.end(), A.outerIndexPtr()) &&
         std::equal(inner_.begin(), inner_.end(), A.innerIndexPtr());
}

// Supernode s's block set to A's entries, and map[row] = the row's place in the block.
void SupernodalCholesky::assemble(int s, const SparseMatrix& A, double* Lx,
                                  std::vector<int>& map) const {
  const int nscol = super_[s + 1] - super_[s], nsrow = pi_[s + 1] - pi_[s];
  std::memset(Lx + px_[s], 0, sizeof(double) * static_cast<size_t>(nsrow) * nscol);
  const double* values = A.valuePtr();
  for (std::int64_t e = entryStart_[s]; e < entryStart_[s + 1]; ++e)
    Lx[entryInL_[e]] += values[entryOfA_[e]];
  const int* rowsS = rows_.data() + pi_[s];
  for (int i = 0; i < nsrow; ++i) map[rowsS[i]] = i;
}

// Columns c0..c1-1 of supernode s minus each descendant's update L_d L_d^T where it meets them,
// the descendants in ascending order (map from assemble(s)).
void SupernodalCholesky::subtractUpdates(int s, int c0, int c1, double* Lx,
                                         const std::vector<int>& map,
                                         std::vector<double>& update) const {
  const int first = super_[s], nsrow = pi_[s + 1] - pi_[s];
  double* block = Lx + px_[s];
  const double one = 1.0, zero = 0.0;
  for (std::int64_t u = updateStart_[s]; u < updateStart_[s + 1]; ++u) {
    const Update& up = updates_[static_cast<size_t>(u)];
    const int d = up.from, ldd = pi_[d + 1] - pi_[d], k = super_[d + 1] - super_[d];
    const int* run = rows_.data() + pi_[d] + up.offset;
    // The part of the run within columns c0..c1-1 (the run is sorted).
    const int lo = static_cast<int>(std::lower_bound(run, run + up.count, first + c0) - run);
    const int hi = static_cast<int>(std::lower_bound(run + lo, run + up.count, first + c1) - run);
    const int count = hi - lo;
    if (count == 0) continue;
    const int m = ldd - up.offset - lo;
    const double* Ld = Lx + px_[d] + up.offset + lo;
    const int* rowsD = run + lo;
    double* C = update.data();
    // C (m x count) = L_d[those rows and below, :] L_d[those rows, :]^T, its top square lower only.
    dsyrk_("L", "N", &count, &k, &one, Ld, &ldd, &zero, C, &m);
    if (m > count) {
      const int below = m - count;
      dgemm_("N", "T", &below, &count, &k, &one, Ld + count, &ldd, Ld, &ldd, &zero, C + count, &m);
    }
    // Where the descendant's rows are consecutive rows of s (often), no map per entry.
    const bool consecutive = map[rowsD[m - 1]] - map[rowsD[0]] == m - 1;
    for (int c = 0; c < count; ++c) {
      double* column = block + static_cast<std::int64_t>(rowsD[c] - first) * nsrow;
      const double* from = C + static_cast<std::int64_t>(c) * m;
      if (consecutive) {
        double* to = column + map[rowsD[0]];
        for (int r = c; r < m; ++r) to[r] -= from[r];
      } else {
        for (int r = c; r < m; ++r) column[map[rowsD[r]]] -= from[r];
      }
    }
  }
}

// Supernode s's diagonal block factorised, the rows below solved against it: -1, or the first
// column whose pivot is not positive.
std::int64_t SupernodalCholesky::finish(int s, double* Lx) const {
  const int first = super_[s], nscol = super_[s + 1] - first, nsrow = pi_[s + 1] - pi_[s];
  double* block = Lx + px_[s];
  int info = 0;
  dpotrf_("L", &nscol, block, &nsrow, &info);
  if (info != 0) return first + info - 1;
  if (nsrow > nscol) {
    const int below = nsrow - nscol;
    const double one = 1.0;
    dtrsm_("R", "L", "T", "N", &below, &nscol, &one, block, &nsrow, block + nscol, &nsrow);
  }
  return -1;
}

// The pieces [cut[c], cut[c + 1]) of columns from..to-1 of a block with `rows` rows whose
// updates each reach the rows at and below their diagonal: about equal work each, the first
// columns weighing more.
std::array<int, SupernodalCholesky::kTopChunks + 1> SupernodalCholesky::balancedCut(int from,
                                                                                    int to,
                                                                                    int rows) {
  double total = 0;
  for (int j = from; j < to; ++j) total += rows - j;
  std::array<int, kTopChunks + 1> cut{};
  cut[0] = from;
  double sum = 0;
  int c = 1;
  for (int j = from; j < to && c < kTopChunks; ++j) {
    sum += rows - j;
    while (c < kTopChunks && sum >= total * c / kTopChunks) cut[static_cast<size_t>(c++)] = j + 1;
  }
  for (; c <= kTopChunks; ++c) cut[static_cast<size_t>(c)] = to;
  return cut;
}

// finish() for a wide top supernode, in panels of kPanelColumns columns (right-looking): each
// panel's diagonal block factorised, the rows below it solved against it and the columns right of
// it updated, both in kTopChunks fixed pieces on the arena's threads (the same bits on any
// number). The last supernodes hold a dense separator that a single dpotrf would leave to one
// core.
std::int64_t SupernodalCholesky::finishInPanels(int s, double* Lx, tbb::task_arena& arena) const {
  const int first = super_[s], nscol = super_[s + 1] - first, nsrow = pi_[s + 1] - pi_[s];
  double* block = Lx + px_[s];
  const double one = 1.0, minusOne = -1.0;
  for (int j0 = 0; j0 < nscol; j0 += kPanelColumns) {
    const int width = std::min(kPanelColumns, nscol - j0), end = j0 + width;
    double* panel = block + static_cast<std::int64_t>(j0) * nsrow;  // column j0, row 0
    int info = 0;
    dpotrf_("L", &width, panel + j0, &nsrow, &info);
    if (info != 0) return first + j0 + info - 1;
    const int below = nsrow - end;
    if (below == 0) break;
    forEachOnArena(arena, kTopChunks, [&](int c) {
      const int r0 = end + below * c / kTopChunks, r1 = end + below * (c + 1) / kTopChunks;
      const int count = r1 - r0;
      if (count > 0)
        dtrsm_("R", "L", "T", "N", &count, &width, &one, panel + j0, &nsrow, panel + r0, &nsrow);
    });
    if (end == nscol) break;
    const std::array<int, kTopChunks + 1> cut = balancedCut(end, nscol, nsrow);
    forEachOnArena(arena, kTopChunks, [&](int c) {
      const int c0 = cut[static_cast<size_t>(c)], count = cut[static_cast<size_t>(c) + 1] - c0;
      if (count == 0) return;
      // Columns c0.. minus L[c0.., panel] L[c0..c0+count-1, panel]^T, their lower part.
      const double* from = panel + c0;
      double* to = block + static_cast<std::int64_t>(c0) * nsrow + c0;
      dsyrk_("L", "N", &count, &width, &minusOne, from, &nsrow, &one, to, &nsrow);
      const int rest = nsrow - c0 - count;
      if (rest > 0)
        dgemm_("N", "T", &rest, &count, &width, &minusOne, from + count, &nsrow, from, &nsrow, &one,
               to + count, &nsrow);
    });
  }
  return -1;
}

std::int64_t SupernodalCholesky::factorize(const SparseMatrix& A, double* Lx,
                                           tbb::task_arena& arena) const {
  if (!matches(A)) throw std::invalid_argument("SupernodalCholesky: A has another pattern");
  const auto groups = static_cast<int>(groups_.size());
  std::vector<std::int64_t> failed(static_cast<size_t>(groups), -1);
  // Each thread's working memory kept for its next factorisation (fresh pages for every one
  // cost page faults, and a build thread factorises again and again); it never reaches the result.
  const auto scratch = [&]() -> Scratch& {
    thread_local Scratch mine;
    mine.map.resize(static_cast<size_t>(n_));
    mine.update.resize(static_cast<size_t>(largestUpdate_));
    return mine;
  };
  forEachOnArena(arena, groups, [&](int g) {
    Scratch& work = scratch();
    std::vector<int>& map = work.map;
    std::vector<double>& update = work.update;
    for (int s : groups_[static_cast<size_t>(g)]) {
      assemble(s, A, Lx, map);
      subtractUpdates(s, 0, super_[s + 1] - super_[s], Lx, map, update);
      failed[static_cast<size_t>(g)] = finish(s, Lx);
      if (failed[static_cast<size_t>(g)] >= 0) return;
    }
  });
  std::int64_t first = -1;
  for (std::int64_t f : failed)
    if (f >= 0 && (first < 0 || f < first)) first = f;
  if (first >= 0) return first;
  // Above the groups the supernodes are few and wide and take most updates: each one's columns in
  // kTopChunks fixed pieces (whatever the thread count, so the same bits), concurrently.
  Scratch& work = scratch();
  const std::vector<int>& map = work.map;
  for (int s : top_) {
    assemble(s, A, Lx, work.map);
    const int nscol = super_[s + 1] - super_[s];
    if (nscol < kChunkedColumns) {
      subtractUpdates(s, 0, nscol, Lx, map, work.update);
    } else {
      // Its columns in pieces of about equal update work.
      const std::array<int, kTopChunks + 1> cut = balancedCut(0, nscol, pi_[s + 1] - pi_[s]);
      forEachOnArena(arena, kTopChunks, [&](int c) {
        subtractUpdates(s, cut[static_cast<size_t>(c)], cut[static_cast<size_t>(c) + 1], Lx, map,
                        scratch().update);
      });
    }
    const std::int64_t f = nscol >= kPanelColumns ? finishInPanels(s, Lx, arena) : finish(s, Lx);
    if (f >= 0) return f;
  }
  return -1;
}

}  // namespace bcassim
