// Union-find (core/detail/DisjointSets.h) against a brute-force labelling of random graphs: the
// sets are the connected components, each rooted at its smallest member whatever the order of
// the unions, and root() after flatten() agrees with find().
#include "d2vdb/core/detail/DisjointSets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace d2vdb {
namespace {

// The smallest vertex of each vertex's connected component, by repeated relaxation.
std::vector<std::uint32_t> componentMinimum(std::size_t count,
                                            const std::vector<std::pair<int, int>>& edges) {
  std::vector<std::uint32_t> label(count);
  for (std::size_t i = 0; i < count; ++i) label[i] = static_cast<std::uint32_t>(i);
  for (bool changed = true; changed;) {
    changed = false;
    for (const auto& [a, b] : edges) {
      const std::uint32_t low = std::min(label[a], label[b]);
      changed = changed || label[a] != low || label[b] != low;
      label[a] = label[b] = low;
    }
  }
  return label;
}

TEST(DisjointSets, SetsAreComponentsRootedAtTheirSmallestMember) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 40; ++trial) {
    const int count = 1 + trial * 13;
    std::uniform_int_distribution<int> vertex(0, count - 1);
    std::vector<std::pair<int, int>> edges(static_cast<std::size_t>(count * (trial % 3) / 2));
    for (auto& edge : edges) edge = {vertex(random), vertex(random)};
    const std::vector<std::uint32_t> expected = componentMinimum(count, edges);
    for (const bool reversed : {false, true}) {
      detail::DisjointSets<std::uint32_t> sets(count);
      if (reversed) std::reverse(edges.begin(), edges.end());
      for (const auto& [a, b] : edges) sets.unite(a, b);
      for (int i = 0; i < count; ++i) {
        EXPECT_EQ(sets.root(i), expected[i]);
        EXPECT_EQ(sets.isRoot(i), expected[i] == static_cast<std::uint32_t>(i));
      }
      sets.flatten();
      for (int i = 0; i < count; ++i) {
        EXPECT_EQ(sets.root(i), expected[i]);
        EXPECT_EQ(sets.find(i), expected[i]);
      }
    }
  }
}

}  // namespace
}  // namespace d2vdb
