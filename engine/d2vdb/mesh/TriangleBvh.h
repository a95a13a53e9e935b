// A bounding-volume hierarchy over the triangles of a mesh.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "d2vdb/mesh/TriangleClosestPoint.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// Triangles as corner indices into a point array (any units, double precision).
using TriangleIndices = TriangleMesh::Triangle;

/// References to the three corners of a triangle.
struct TriangleCorners {
  const Eigen::Vector3d& a;
  const Eigen::Vector3d& b;
  const Eigen::Vector3d& c;
};

/// The corners of `triangle` in `points` (indices not checked).
inline TriangleCorners cornersOf(const std::vector<Eigen::Vector3d>& points,
                                 const TriangleIndices& triangle) {
  return {points[triangle[0]], points[triangle[1]], points[triangle[2]]};
}

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

/// What a depth-first walk over a TriangleBvh does after visiting a node (walkDepthFirst()).
enum class BvhStep {
  kSkip,                ///< nothing below this node (a leaf's visit, or a pruned subtree)
  kChildren,            ///< the left child's subtree, then the right child's
  kChildrenRightFirst,  ///< the right child's subtree, then the left child's
  kStop,                ///< end the walk
};

/// Walks the nodes of `bvh` depth first from the root with an explicit stack (nothing for an
/// empty tree). `visit(index, node)` handles a node and returns the BvhStep to take next; it must
/// not return kChildren or kChildrenRightFirst for a leaf. Inline: every distance and sign query
/// of a mesh walks the tree.
template <class Visit>
void walkDepthFirst(const TriangleBvh& bvh, Visit&& visit) {
  const std::vector<TriangleBvh::Node>& nodes = bvh.nodes();
  if (nodes.empty()) return;
  // Median splits keep the depth below 33 for 2^32 triangles; each level adds one entry.
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::uint32_t index = stack[--top];
    const TriangleBvh::Node& node = nodes[index];
    switch (visit(index, node)) {
      case BvhStep::kSkip:
        break;
      case BvhStep::kChildren:
        stack[top++] = node.right;
        stack[top++] = index + 1;
        break;
      case BvhStep::kChildrenRightFirst:
        stack[top++] = index + 1;
        stack[top++] = node.right;
        break;
      case BvhStep::kStop:
        return;
    }
  }
}

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

}  // namespace d2vdb
