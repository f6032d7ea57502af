// Sets of items 0..n-1 joined pairwise (union-find), shared by the steps
// that group facets or tetrahedra across the sides they share.
#pragma once

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

namespace vd {

class DisjointSets {
 public:
  explicit DisjointSets(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }

  // The set's root, with path halving on the way.
  int find(int x) {
    while (parent_[static_cast<size_t>(x)] != x)
      x = parent_[static_cast<size_t>(x)] = parent_[static_cast<size_t>(parent_[static_cast<size_t>(x)])];
    return x;
  }

  // The lower root stays: every set's root is its lowest item, whatever the
  // order of the joins, so numberings by root follow the items' order.
  void join(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
  }

  // Every item's root, in the sets' own storage (no second vector of n at
  // a caller's peak).
  std::vector<int> roots() && {
    for (size_t x = 0; x < parent_.size(); ++x) parent_[x] = find(static_cast<int>(x));
    return std::move(parent_);
  }

 private:
  std::vector<int> parent_;
};

}  // namespace vd
