// Union-find over the integers 0..n-1, shared by the modules that label connected pieces (mesh
// components, band voxel groups, support-function regions).
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

namespace d2vdb::detail {

/// Disjoint sets of 0..size-1 with path halving. The root of a set is always its smallest member,
/// so labels do not depend on the order of unite() calls. find() and unite() write (path
/// halving): call them from one thread; after flatten(), root() may be called from any number of
/// threads at once.
template <class Index>
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t size) : parent_(size) {
    std::iota(parent_.begin(), parent_.end(), Index{0});
  }

  /// The root (smallest member) of the set holding `element`, halving the path to it.
  Index find(Index element) {
    while (parent_[element] != element) {
      parent_[element] = parent_[parent_[element]];
      element = parent_[element];
    }
    return element;
  }

  /// Merges the sets of `a` and `b`; the smaller root becomes the root of both.
  void unite(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (a < b) {
      parent_[b] = a;
    } else if (b < a) {
      parent_[a] = b;
    }
  }

  /// Whether `element` is the root of its set.
  bool isRoot(Index element) const { return parent_[element] == element; }

  /// Points every element at its root, so that root() answers in one step.
  void flatten() {
    for (std::size_t element = 0; element < parent_.size(); ++element) {
      parent_[element] = parent_[parent_[element]];  // the parent's parent is its root already
    }
  }

  /// The root of `element`'s set without writing: safe from many threads; one step after flatten().
  Index root(Index element) const {
    while (parent_[element] != element) element = parent_[element];
    return element;
  }

 private:
  std::vector<Index> parent_;
};

}  // namespace d2vdb::detail
