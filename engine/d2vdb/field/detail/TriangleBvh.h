// A bounding-volume hierarchy over the triangles of a mesh.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "d2vdb/field/detail/TriangleClosestPoint.h"

namespace d2vdb::detail {

/// Triangles as corner indices into a point array (any units, double precision).
using TriangleIndices = std::array<std::uint32_t, 3>;

/// A binary tree over triangles: each node keeps the axis-aligned box of its triangles' corners
/// and a range of `order()`; an inner node splits its triangles at the median of their centroids
/// along the box's longest side, down to leaves of at most `leafSize` triangles. Nodes are in
/// depth-first order: an inner node's left child follows it and `right` names the other one.
/// Building is parallel (TBB) and deterministic: the tree depends on the input only (a subtree of
/// n triangles always occupies the same number of nodes, so every subtree's place in the node
/// array is known before it is built). Holds references to neither input.
class TriangleBvh {
 public:
  struct Node {
    Eigen::Vector3d low;  ///< box of the node's triangles (corners included)
    Eigen::Vector3d high;
    std::uint32_t begin = 0;  ///< the node's triangles are order()[begin, end)
    std::uint32_t end = 0;
    std::uint32_t right = 0;  ///< index of the right child; 0 for a leaf
    bool isLeaf() const { return right == 0; }
  };

  /// Builds the tree; an empty triangle list gives an empty tree (no nodes). Corner indices must
  /// be valid (not checked here).
  TriangleBvh(const std::vector<Eigen::Vector3d>& points,
              const std::vector<TriangleIndices>& triangles, std::uint32_t leafSize = 8);

  const std::vector<Node>& nodes() const { return nodes_; }
  /// Triangle indices in leaf order.
  const std::vector<std::uint32_t>& order() const { return order_; }
  std::uint32_t leafSize() const { return leafSize_; }

 private:
  std::uint32_t leafSize_;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> order_;
};

/// The triangle nearest to a point and its closest point on it.
struct NearestTriangle {
  std::uint32_t triangle = std::numeric_limits<std::uint32_t>::max();  ///< none: empty tree
  TriangleClosestPoint closest;
  double squaredDistance = std::numeric_limits<double>::infinity();
};

/// Exact nearest triangle to `q` (branch and bound over the boxes, nearer child first); among
/// equally near triangles the first found in that fixed order. `points` and `triangles` are
/// those the tree was built on.
NearestTriangle nearestTriangle(const TriangleBvh& bvh, const std::vector<Eigen::Vector3d>& points,
                                const std::vector<TriangleIndices>& triangles,
                                const Eigen::Vector3d& q);

}  // namespace d2vdb::detail
