#pragma once
/// \file
/// A plain union-find (disjoint sets) with path halving and union by size, shared by the
/// stc sources (internal: not installed). Roots are arbitrary members of their class; callers
/// that number classes do so by first appearance, so the numbering does not depend on them.

#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

namespace stcweave::stc::detail {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n), size_(n, 1) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }
  std::size_t find(std::size_t a) {
    while (parent_[a] != a) {
      parent_[a] = parent_[parent_[a]];
      a = parent_[a];
    }
    return a;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
  }

 private:
  std::vector<std::size_t> parent_;
  std::vector<std::size_t> size_;
};

}  // namespace stcweave::stc::detail
