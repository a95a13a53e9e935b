#include "d2vdb/mesh/TriangleBvh.h"

#include <tbb/task_group.h>

#include <algorithm>
#include <limits>
#include <numeric>

namespace d2vdb {
namespace {

/// Number of nodes of a subtree over `count` triangles (a function of the count only).
std::uint32_t subtreeNodes(std::uint32_t count, std::uint32_t leafSize) {
  if (count <= leafSize) return 1;
  const std::uint32_t left = count / 2;
  return 1 + subtreeNodes(left, leafSize) + subtreeNodes(count - left, leafSize);
}

/// Subtrees with fewer triangles than this are built by the calling task.
constexpr std::uint32_t kSerialBuild = 4096;

class Builder {
 public:
  Builder(const std::vector<Eigen::Vector3d>& points, const std::vector<TriangleIndices>& triangles,
          std::uint32_t leafSize, std::vector<TriangleBvh::Node>& nodes,
          std::vector<std::uint32_t>& order)
      : points_(points), triangles_(triangles), leafSize_(leafSize), nodes_(nodes), order_(order) {
    centroids_.resize(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      const TriangleIndices& tri = triangles[t];
      centroids_[t] = (points[tri[0]] + points[tri[1]] + points[tri[2]]) / 3.0;
    }
  }

  /// Builds the subtree over order_[begin, end) into nodes_[nodeIndex, ...).
  void build(std::uint32_t nodeIndex, std::uint32_t begin, std::uint32_t end) {
    TriangleBvh::Node& node = nodes_[nodeIndex];
    node.begin = begin;
    node.end = end;
    const std::uint32_t count = end - begin;
    if (count <= leafSize_) {
      node.right = 0;
      setLeafBox(node);
      return;
    }
    // Split at the median centroid along the longest side of the centroids' box; ties broken by
    // triangle index so that the order is a function of the input alone.
    Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d high = -low;
    for (std::uint32_t i = begin; i < end; ++i) {
      low = low.cwiseMin(centroids_[order_[i]]);
      high = high.cwiseMax(centroids_[order_[i]]);
    }
    int axis = 0;
    (high - low).maxCoeff(&axis);
    const std::uint32_t middle = begin + count / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                     [this, axis](std::uint32_t x, std::uint32_t y) {
                       const double cx = centroids_[x][axis];
                       const double cy = centroids_[y][axis];
                       return cx < cy || (cx == cy && x < y);
                     });
    const std::uint32_t leftIndex = nodeIndex + 1;
    const std::uint32_t rightIndex = leftIndex + subtreeNodes(middle - begin, leafSize_);
    node.right = rightIndex;
    if (count >= kSerialBuild) {
      tbb::task_group group;
      group.run([&] { build(leftIndex, begin, middle); });
      build(rightIndex, middle, end);
      group.wait();
    } else {
      build(leftIndex, begin, middle);
      build(rightIndex, middle, end);
    }
    const TriangleBvh::Node& left = nodes_[leftIndex];
    const TriangleBvh::Node& right = nodes_[rightIndex];
    nodes_[nodeIndex].low = left.low.cwiseMin(right.low);
    nodes_[nodeIndex].high = left.high.cwiseMax(right.high);
  }

 private:
  void setLeafBox(TriangleBvh::Node& node) const {
    Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d high = -low;
    for (std::uint32_t i = node.begin; i < node.end; ++i) {
      for (const std::uint32_t corner : triangles_[order_[i]]) {
        low = low.cwiseMin(points_[corner]);
        high = high.cwiseMax(points_[corner]);
      }
    }
    node.low = low;
    node.high = high;
  }

  const std::vector<Eigen::Vector3d>& points_;
  const std::vector<TriangleIndices>& triangles_;
  const std::uint32_t leafSize_;
  std::vector<TriangleBvh::Node>& nodes_;
  std::vector<std::uint32_t>& order_;
  std::vector<Eigen::Vector3d> centroids_;
};

}  // namespace

namespace {

double squaredDistanceToBox(const Eigen::Vector3d& q, const TriangleBvh::Node& node) {
  return (node.low - q).cwiseMax(q - node.high).cwiseMax(Eigen::Vector3d::Zero()).squaredNorm();
}

}  // namespace

NearestTriangle nearestTriangle(const TriangleBvh& bvh, const std::vector<Eigen::Vector3d>& points,
                                const std::vector<TriangleIndices>& triangles,
                                const Eigen::Vector3d& q) {
  NearestTriangle best;
  const std::vector<TriangleBvh::Node>& nodes = bvh.nodes();
  walkDepthFirst(bvh, [&](std::uint32_t index, const TriangleBvh::Node& node) {
    if (squaredDistanceToBox(q, node) >= best.squaredDistance) return BvhStep::kSkip;
    if (node.isLeaf()) {
      for (std::uint32_t i = node.begin; i < node.end; ++i) {
        const std::uint32_t t = bvh.order()[i];
        const TriangleIndices& tri = triangles[t];
        const TriangleClosestPoint closest =
            closestPointOnTriangle(q, points[tri[0]], points[tri[1]], points[tri[2]]);
        const double d2 = (closest.point - q).squaredNorm();
        if (d2 < best.squaredDistance) best = {t, closest, d2};
      }
      return BvhStep::kSkip;
    }
    // The nearer child first, so that its triangles tighten the bound before the other's box.
    return squaredDistanceToBox(q, nodes[index + 1]) <= squaredDistanceToBox(q, nodes[node.right])
               ? BvhStep::kChildren
               : BvhStep::kChildrenRightFirst;
  });
  return best;
}

TriangleBvh::TriangleBvh(const std::vector<Eigen::Vector3d>& points,
                         const std::vector<TriangleIndices>& triangles, std::uint32_t leafSize)
    : leafSize_(std::max<std::uint32_t>(leafSize, 1)) {
  if (triangles.empty()) return;
  const auto count = static_cast<std::uint32_t>(triangles.size());
  order_.resize(count);
  std::iota(order_.begin(), order_.end(), std::uint32_t{0});
  nodes_.resize(subtreeNodes(count, leafSize_));
  Builder builder(points, triangles, leafSize_, nodes_, order_);
  builder.build(0, 0, count);
}

}  // namespace d2vdb
