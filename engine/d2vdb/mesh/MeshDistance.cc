#include "d2vdb/mesh/MeshDistance.h"

#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

/// The mesh's positions in double precision, checked finite.
std::vector<Eigen::Vector3d> checkedPoints(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) throw InputError("the mesh has no triangles to measure against");
  std::vector<Eigen::Vector3d> points;
  points.reserve(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!mesh.positions[i].allFinite()) {
      throw InputError("mesh vertex " + std::to_string(i) + " has a non-finite coordinate");
    }
    points.push_back(mesh.positions[i].cast<double>());
  }
  return points;
}

/// The mesh's triangles, checked to index existing vertices.
const std::vector<TriangleIndices>& checkedTriangles(const TriangleMesh& mesh) {
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const TriangleMesh::Index corner : mesh.triangles[t]) {
      if (corner >= mesh.positions.size()) {
        throw InputError("mesh triangle " + std::to_string(t) + " names vertex " +
                         std::to_string(corner) + " of " + std::to_string(mesh.positions.size()));
      }
    }
  }
  return mesh.triangles;
}

}  // namespace

MeshDistance::MeshDistance(const TriangleMesh& mesh)
    : points_(checkedPoints(mesh)), triangles_(checkedTriangles(mesh)), bvh_(points_, triangles_) {}

MeshClosestPoint MeshDistance::closestPoint(const Eigen::Vector3d& query) const {
  if (!query.allFinite()) throw InputError("the query point has a non-finite coordinate");
  const NearestTriangle nearest = nearestTriangle(bvh_, points_, triangles_, query);
  return {nearest.triangle, nearest.closest.point, std::sqrt(nearest.squaredDistance)};
}

}  // namespace d2vdb
