#include "d2vdb/mesh/MeshMeasures.h"

#include <Eigen/Geometry>

#include <limits>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/detail/MeshIndexCheck.h"

namespace d2vdb {

BoundingBox boundingBox(const TriangleMesh& mesh) {
  if (mesh.positions.empty())
    throw InputError("cannot take the bounding box of a mesh without vertices");
  detail::checkTriangleIndices(mesh, "cannot take the bounding box of the mesh");
  Eigen::Vector3f low = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f high = -low;
  const auto include = [&](const Eigen::Vector3f& point) {
    low = low.cwiseMin(point);
    high = high.cwiseMax(point);
  };
  if (mesh.triangles.empty()) {
    for (const Eigen::Vector3f& position : mesh.positions) include(position);
  } else {
    std::vector<bool> seen(mesh.positions.size(), false);
    for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
      for (const TriangleMesh::Index index : triangle) {
        if (seen[index]) continue;
        seen[index] = true;
        include(mesh.positions[index]);
      }
    }
  }
  BoundingBox box;
  box.min = low.cast<double>();
  box.max = high.cast<double>();
  return box;
}

double surfaceArea(const TriangleMesh& mesh) {
  detail::checkTriangleIndices(mesh, "cannot measure the surface area of the mesh");
  double area = 0.0;
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    const Eigen::Vector3d a = mesh.positions[triangle[0]].cast<double>();
    const Eigen::Vector3d b = mesh.positions[triangle[1]].cast<double>();
    const Eigen::Vector3d c = mesh.positions[triangle[2]].cast<double>();
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  return area;
}

}  // namespace d2vdb
