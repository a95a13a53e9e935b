// Bounding-box hierarchy for exact nearest points (NearestPointTree.h).
#include "d2vdb/field/detail/NearestPointTree.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {
namespace {

/// Points per leaf: a leaf's distances are computed together (vectorised), so leaves are wide.
constexpr std::uint32_t kLeafSize = 32;
/// Bound on the tree depth (below 27 for 2^31 points, 32 to a leaf) and so on the search stacks
/// (a depth-first search holds at most one entry per level plus one).
constexpr std::size_t kMaxDepth = 64;
/// Subtrees with fewer points are built serially.
constexpr std::uint32_t kParallelBuild = 16384;
/// Relative slack on box pruning: a box is skipped only when its distance exceeds the best one by
/// more than float rounding could explain, so no point at the best distance is ever missed.
constexpr float kPruneSlack = 1.0f + 1e-6f;

/// Nodes of the subtree over `count` points (the split puts count / 2 on the left).
std::uint32_t subtreeNodes(std::uint32_t count) {
  if (count <= kLeafSize) return 1;
  return 1 + subtreeNodes(count / 2) + subtreeNodes(count - count / 2);
}

}  // namespace

NearestPointTree::NearestPointTree(const std::vector<Eigen::Vector3f>& points) {
  if (points.empty()) throw InputError("nearest-point tree: no points");
  if (points.size() >= (std::size_t{1} << 31)) {
    throw InputError("nearest-point tree: " + std::to_string(points.size()) +
                     " points, more than 32-bit indices address");
  }
  for (const Eigen::Vector3f& p : points) {
    if (!p.allFinite()) throw InputError("nearest-point tree: a point is not finite");
  }
  const auto count = static_cast<std::uint32_t>(points.size());
  std::vector<Item> items(count);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, count, 4096),
                    [&](const tbb::blocked_range<std::uint32_t>& range) {
                      for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
                        items[i] = {points[i], i};
                      }
                    });
  nodes_.resize(subtreeNodes(count));
  build(items, 0, 0, count);
  xs_.resize(count);
  ys_.resize(count);
  zs_.resize(count);
  originalIndex_.resize(count);
  position_.resize(count);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, count, 4096),
                    [&](const tbb::blocked_range<std::uint32_t>& range) {
                      for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
                        xs_[i] = items[i].point.x();
                        ys_[i] = items[i].point.y();
                        zs_[i] = items[i].point.z();
                        originalIndex_[i] = items[i].index;
                        position_[items[i].index] = i;
                      }
                    });
}

void NearestPointTree::build(std::vector<Item>& items, std::uint32_t node, std::uint32_t begin,
                             std::uint32_t end) {
  // Tight box of the range.
  Node& current = nodes_[node];
  current.lo = {items[begin].point.x(), items[begin].point.y(), items[begin].point.z()};
  current.hi = current.lo;
  for (std::uint32_t i = begin + 1; i < end; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      current.lo[axis] = std::min(current.lo[axis], items[i].point[axis]);
      current.hi[axis] = std::max(current.hi[axis], items[i].point[axis]);
    }
  }
  current.begin = begin;
  current.end = end;
  const std::uint32_t count = end - begin;
  if (count <= kLeafSize) {
    current.second = 0;
    return;
  }
  // Median split along the longest side; ties in the coordinate are ordered by input index, so
  // the tree depends only on the points.
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (current.hi[a] - current.lo[a] > current.hi[axis] - current.lo[axis]) axis = a;
  }
  const std::uint32_t middle = begin + count / 2;
  std::nth_element(items.begin() + begin, items.begin() + middle, items.begin() + end,
                   [axis](const Item& a, const Item& b) {
                     const float pa = a.point[axis], pb = b.point[axis];
                     return pa != pb ? pa < pb : a.index < b.index;
                   });
  const std::uint32_t left = node + 1;
  const std::uint32_t right = left + subtreeNodes(count / 2);
  current.second = right;
  current.axis = static_cast<std::uint32_t>(axis);
  current.split = items[middle].point[axis];
  if (count >= kParallelBuild) {
    tbb::parallel_invoke([&] { build(items, left, begin, middle); },
                         [&] { build(items, right, middle, end); });
  } else {
    build(items, left, begin, middle);
    build(items, right, middle, end);
  }
}

inline float NearestPointTree::pointDistance(std::uint32_t position,
                                             const Eigen::Vector3f& query) const {
  const float dx = xs_[position] - query.x();
  const float dy = ys_[position] - query.y();
  const float dz = zs_[position] - query.z();
  return dx * dx + dy * dy + dz * dz;
}

inline float NearestPointTree::squaredDistance(const Node& node, const Eigen::Vector3f& query) {
  const float gx = std::max(std::max(node.lo[0] - query.x(), query.x() - node.hi[0]), 0.0f);
  const float gy = std::max(std::max(node.lo[1] - query.y(), query.y() - node.hi[1]), 0.0f);
  const float gz = std::max(std::max(node.lo[2] - query.z(), query.z() - node.hi[2]), 0.0f);
  return gx * gx + gy * gy + gz * gz;
}

void NearestPointTree::searchSubtree(std::uint32_t root, const Eigen::Vector3f& query,
                                     Nearest& best, float& bound) const {
  // Locals (no aliasing through the references) and separate node and distance stacks (each
  // entry is read back with the width it was written with).
  Nearest nearest = best;
  float limit = bound;
  std::array<std::uint32_t, kMaxDepth> stackNode;
  std::array<float, kMaxDepth> stackDistance;
  std::size_t top = 0;
  stackNode[top] = root;
  stackDistance[top++] = squaredDistance(nodes_[root], query);
  while (top > 0) {
    --top;
    if (stackDistance[top] > limit) continue;
    const std::uint32_t index = stackNode[top];
    const Node& node = nodes_[index];
    if (node.second == 0) {
      const std::uint32_t count = node.end - node.begin;
      std::array<float, kLeafSize> squared;
      for (std::uint32_t k = 0; k < count; ++k) {
        squared[k] = pointDistance(node.begin + k, query);
      }
      for (std::uint32_t k = 0; k < count; ++k) {
        if (squared[k] < nearest.squaredDistance ||
            (squared[k] == nearest.squaredDistance &&
             originalIndex_[node.begin + k] < nearest.index)) {
          nearest = {originalIndex_[node.begin + k], squared[k]};
          limit = squared[k] * kPruneSlack;
        }
      }
      continue;
    }
    const std::uint32_t first = index + 1;
    const float firstDistance = squaredDistance(nodes_[first], query);
    const float secondDistance = squaredDistance(nodes_[node.second], query);
    // Push the farther child first so that the nearer one is searched first.
    const bool firstNearer = firstDistance <= secondDistance;
    const float nearerDistance = firstNearer ? firstDistance : secondDistance;
    const float fartherDistance = firstNearer ? secondDistance : firstDistance;
    if (fartherDistance <= limit) {
      stackNode[top] = firstNearer ? node.second : first;
      stackDistance[top++] = fartherDistance;
    }
    if (nearerDistance <= limit) {
      stackNode[top] = firstNearer ? first : node.second;
      stackDistance[top++] = nearerDistance;
    }
  }
  best = nearest;
  bound = limit;
}

NearestPointTree::Nearest NearestPointTree::nearest(const Eigen::Vector3f& query,
                                                    std::uint32_t hint) const {
  const std::uint32_t start = hint < position_.size() ? position_[hint] : position_[0];
  Nearest best{originalIndex_[start], pointDistance(start, query)};
  float bound = best.squaredDistance * kPruneSlack;  // boxes farther than this are skipped

  // Down the split planes to the leaf whose cell holds the query, remembering each cell.
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  std::array<float, 3> lo{-kInfinity, -kInfinity, -kInfinity};
  std::array<float, 3> hi{kInfinity, kInfinity, kInfinity};
  std::array<std::uint32_t, kMaxDepth> pathNode;
  std::array<std::array<float, 3>, kMaxDepth> pathLo;
  std::array<std::array<float, 3>, kMaxDepth> pathHi;
  std::size_t depth = 0;
  std::uint32_t current = 0;
  while (nodes_[current].second != 0) {
    pathNode[depth] = current;
    pathLo[depth] = lo;
    pathHi[depth] = hi;
    ++depth;
    const Node& node = nodes_[current];
    if (query[static_cast<int>(node.axis)] < node.split) {
      current = current + 1;
      hi[node.axis] = node.split;
    } else {
      current = node.second;
      lo[node.axis] = node.split;
    }
  }
  pathNode[depth] = current;
  pathLo[depth] = lo;
  pathHi[depth] = hi;
  searchSubtree(current, query, best, bound);

  // Up: once the ball through the best point lies inside a searched cell, no point outside can be
  // nearer; until then, search the sibling of each searched cell.
  for (; depth > 0; --depth) {
    bool inside = true;
    for (int axis = 0; axis < 3 && inside; ++axis) {
      const float below = query[axis] - pathLo[depth][axis];
      const float above = pathHi[depth][axis] - query[axis];
      inside = below * below > bound && above * above > bound;
    }
    if (inside) break;
    const std::uint32_t parent = pathNode[depth - 1];
    const std::uint32_t sibling =
        pathNode[depth] == parent + 1 ? nodes_[parent].second : parent + 1;
    searchSubtree(sibling, query, best, bound);
  }
  return best;
}

}  // namespace d2vdb::detail
