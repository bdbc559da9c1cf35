// Axis-aligned bounding-box hierarchy over arbitrary primitives (tets, triangles), the spatial
// index behind point location and closest-point queries. Queries allocate nothing.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <limits>
#include <vector>

#include "bcassim/Types.h"

namespace bcassim {

class AabbTree {
 public:
  struct Box {
    Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());
    void extend(const Vec3& p) {
      min = min.cwiseMin(p);
      max = max.cwiseMax(p);
    }
    void extend(const Box& b) {
      min = min.cwiseMin(b.min);
      max = max.cwiseMax(b.max);
    }
    bool contains(const Vec3& p, double tol) const {
      return (p.array() >= min.array() - tol).all() && (p.array() <= max.array() + tol).all();
    }
    double squaredDistance(const Vec3& p) const {
      return (min - p).cwiseMax(p - max).cwiseMax(0.0).squaredNorm();
    }
  };

  AabbTree() = default;
  // boxes: one box per primitive, in any units (metres here); primitive ids are the indices.
  explicit AabbTree(const std::vector<Box>& boxes);

  // Moves the primitives without rebuilding: `boxes` (one per primitive, as given to the
  // constructor) become the leaves' and every node's box is recomputed bottom-up. Queries stay
  // exact whatever the motion; only their speed depends on how far the primitives moved from where
  // the tree was built. O(n) against the build's O(n log n). Throws std::invalid_argument when
  // the count differs from the tree's.
  void refit(const std::vector<Box>& boxes);

  bool empty() const { return nodes_.empty(); }
  const Box& bounds() const { return nodes_.front().box; }

  // Calls visit(primitive) for every primitive whose box contains p (boxes grown by tol);
  // stops early when visit returns true. Returns whether it stopped early.
  template <class Visit>
  bool visitContaining(const Vec3& p, double tol, Visit&& visit) const;

  // Nearest primitive: sqDist(primitive, bestSoFar) returns the squared distance from the query
  // to that primitive (it may give up early and return anything >= bestSoFar). Returns the id, or
  // -1 when the tree is empty; bestSq receives the squared distance.
  template <class SqDist>
  int nearest(const Vec3& p, SqDist&& sqDist, double& bestSq) const;

 private:
  struct Node {
    Box box;
    int first = 0;  // leaf: first index in order_; inner: index of the left child
    int count = 0;  // leaf: number of primitives; 0 marks an inner node (right child = first + 1)
  };
  // Depth is bounded by log2(#primitives / leaf size) + slack; 64 covers any mesh that fits in int.
  static constexpr int kMaxDepth = 64;
  static constexpr int kLeafSize = 4;

  void build(int self, const std::vector<Vec3>& centres, const std::vector<Box>& boxes, int begin,
             int end, int depth);

  std::vector<Node> nodes_;
  std::vector<int> order_;  // primitive ids, leaves reference contiguous ranges
};

template <class Visit>
bool AabbTree::visitContaining(const Vec3& p, double tol, Visit&& visit) const {
  if (nodes_.empty()) return false;
  int stack[kMaxDepth + 1];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!n.box.contains(p, tol)) continue;
    if (n.count > 0) {
      for (int k = n.first; k < n.first + n.count; ++k)
        if (visit(order_[k])) return true;
    } else {
      stack[top++] = n.first + 1;
      stack[top++] = n.first;
    }
  }
  return false;
}

template <class SqDist>
int AabbTree::nearest(const Vec3& p, SqDist&& sqDist, double& bestSq) const {
  bestSq = std::numeric_limits<double>::infinity();
  int best = -1;
  if (nodes_.empty()) return best;
  // Depth-first, nearer child first, pruned by box distance: cheap and allocation-free.
  struct Entry {
    int node;
    double sq;
  };
  Entry stack[kMaxDepth + 2];
  int top = 0;
  stack[top++] = {0, nodes_[0].box.squaredDistance(p)};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.sq >= bestSq) continue;
    const Node& n = nodes_[e.node];
    if (n.count > 0) {
      for (int k = n.first; k < n.first + n.count; ++k) {
        const double d = sqDist(order_[k], bestSq);
        if (d < bestSq) {
          bestSq = d;
          best = order_[k];
        }
      }
      continue;
    }
    const int l = n.first, r = n.first + 1;
    const double dl = nodes_[l].box.squaredDistance(p), dr = nodes_[r].box.squaredDistance(p);
    if (dl <= dr) {
      stack[top++] = {r, dr};
      stack[top++] = {l, dl};
    } else {
      stack[top++] = {l, dl};
      stack[top++] = {r, dr};
    }
  }
  return best;
}

}  // namespace bcassim
