// Exact nearest-point search over a fixed float point set, for queries far from the points.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace d2vdb::detail {

/// A k-d tree over a fixed set of points (any units; float coordinates), answering exact
/// nearest-point queries, made for queries far from a surface-like point set (the field's
/// coarse-level cell centres, up to many sample spacings off the target). Nodes split their points
/// at the median of their box's longest side, down to leaves of at most 32 points, and keep the
/// tight box of their points. A query starts in the leaf whose cell holds it and climbs: it stops
/// at the first ancestor whose cell contains the ball reaching the best point so far, and on the
/// way searches each sibling subtree whose tight box meets that ball (nearer child first). Leaf
/// distances are computed together from coordinate arrays, which the compiler vectorises.
///
/// Building is parallel (TBB) and deterministic; queries are const and thread-safe. Distances are
/// compared as float squared distances (dx * dx + dy * dy + dz * dz in float); ties go to the
/// lowest point index, so the answer never depends on the hint, the thread or the order of queries.
class NearestPointTree {
 public:
  /// Copies and sorts the points. Throws InputError when there are none, 2^31 or more, or one is
  /// not finite.
  explicit NearestPointTree(const std::vector<Eigen::Vector3f>& points);

  /// The nearest point to `query`: its index in the constructor's vector and its float squared
  /// distance. `hint` is any point index (out of range counts as 0); a hint near the answer, such
  /// as the previous answer of a coherent sequence of queries, makes the search faster.
  struct Nearest {
    std::uint32_t index = 0;
    float squaredDistance = 0.0f;
  };
  Nearest nearest(const Eigen::Vector3f& query, std::uint32_t hint) const;

  std::size_t size() const { return originalIndex_.size(); }

 private:
  /// A node in depth-first order: its left child follows it, `second` is the right child's index;
  /// a leaf (second == 0) holds positions [begin, end) of the point arrays. An inner node's left
  /// subtree has the points with coordinate `axis` <= split, the right one those with >= split.
  struct Node {
    std::array<float, 3> lo;  ///< tight box of the node's points
    std::array<float, 3> hi;
    std::uint32_t begin = 0;
    std::uint32_t end = 0;
    std::uint32_t second = 0;
    float split = 0.0f;
    std::uint32_t axis = 0;
  };
  /// A point and its input index, while building.
  struct Item {
    Eigen::Vector3f point;
    std::uint32_t index;
  };
  static float squaredDistance(const Node& node, const Eigen::Vector3f& query);
  /// Float squared distance from the point at tree position `position` to `query`.
  float pointDistance(std::uint32_t position, const Eigen::Vector3f& query) const;
  /// Fills node `node` and its subtree from items [begin, end), which it reorders.
  void build(std::vector<Item>& items, std::uint32_t node, std::uint32_t begin, std::uint32_t end);
  /// Depth-first search of the subtree at `root`, nearer child first, skipping boxes beyond
  /// `bound`; updates best and bound.
  void searchSubtree(std::uint32_t root, const Eigen::Vector3f& query, Nearest& best,
                     float& bound) const;

  std::vector<float> xs_, ys_, zs_;           ///< point coordinates in tree order
  std::vector<std::uint32_t> originalIndex_;  ///< their indices in the input
  std::vector<std::uint32_t> position_;       ///< input index -> position in tree order
  std::vector<Node> nodes_;
};

}  // namespace d2vdb::detail
