// Exact closest points and distances from points to a triangle mesh.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "d2vdb/mesh/TriangleBvh.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// The point of a mesh closest to a query point.
struct MeshClosestPoint {
  std::uint32_t triangle = 0;                       ///< index into the mesh's triangles
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< world units
  double distance = 0.0;                            ///< |point - query|, world units
};

/// Closest points on the triangles of a mesh, from a TriangleBvh over them (corners converted to
/// double precision once). Degenerate triangles are allowed: their closest points lie on an edge
/// or a corner. The object copies what it needs from the mesh; queries are const and may run on
/// any number of threads.
class MeshDistance {
 public:
  /// Throws InputError for a mesh without triangles, a corner index out of range or a non-finite
  /// position.
  explicit MeshDistance(const TriangleMesh& mesh);

  /// The exact closest point of the mesh to `query` (among equally near triangles, the first in
  /// the tree's fixed order, so the answer does not depend on threads). Throws InputError for a
  /// non-finite query.
  MeshClosestPoint closestPoint(const Eigen::Vector3d& query) const;

  std::size_t triangleCount() const { return triangles_.size(); }

 private:
  std::vector<Eigen::Vector3d> points_;
  std::vector<TriangleIndices> triangles_;
  TriangleBvh bvh_;
};

}  // namespace d2vdb
