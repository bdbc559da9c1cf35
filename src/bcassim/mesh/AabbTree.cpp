#include "bcassim/mesh/AabbTree.h"

#include <numeric>
#include <stdexcept>

namespace bcassim {

AabbTree::AabbTree(const std::vector<Box>& boxes) {
  const int n = static_cast<int>(boxes.size());
  if (n == 0) return;
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0);
  std::vector<Vec3> centres(n);
  for (int i = 0; i < n; ++i) centres[i] = 0.5 * (boxes[i].min + boxes[i].max);
  nodes_.reserve(2 * (n / kLeafSize + 1));
  nodes_.emplace_back();
  build(0, centres, boxes, 0, n, 0);
}

void AabbTree::refit(const std::vector<Box>& boxes) {
  if (boxes.size() != order_.size())
    throw std::invalid_argument("AabbTree::refit: one box per primitive of the tree expected");
  // Children are allocated after their parent: from the last node back, both are done first.
  for (auto i = static_cast<int>(nodes_.size()) - 1; i >= 0; --i) {
    Node& n = nodes_[static_cast<size_t>(i)];
    Box box;
    if (n.count > 0) {
      for (int k = n.first; k < n.first + n.count; ++k) box.extend(boxes[order_[k]]);
    } else {
      box.extend(nodes_[n.first].box);
      box.extend(nodes_[n.first + 1].box);
    }
    n.box = box;
  }
}

void AabbTree::build(int self, const std::vector<Vec3>& centres, const std::vector<Box>& boxes,
                     int begin, int end, int depth) {
  Box box, centreBox;
  for (int k = begin; k < end; ++k) {
    box.extend(boxes[order_[k]]);
    centreBox.extend(centres[order_[k]]);
  }
  nodes_[self].box = box;
  if (end - begin <= kLeafSize || depth >= kMaxDepth - 1) {
    nodes_[self].first = begin;
    nodes_[self].count = end - begin;
    return;
  }
  // Median split along the longest extent of the centres keeps the tree balanced (depth ~log n).
  int axis;
  (centreBox.max - centreBox.min).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int a, int b) { return centres[a](axis) < centres[b](axis); });
  // Siblings are allocated as a pair so an inner node needs only the left child's index.
  const int left = static_cast<int>(nodes_.size());
  nodes_[self].first = left;
  nodes_[self].count = 0;
  nodes_.resize(nodes_.size() + 2);
  build(left, centres, boxes, begin, mid, depth + 1);
  build(left + 1, centres, boxes, mid, end, depth + 1);
}

}  // namespace bcassim
