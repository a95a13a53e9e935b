#include "d2vdb/mesh/VertexNormals.h"

#include <Eigen/Geometry>

#include <cmath>
#include <vector>

#include "d2vdb/mesh/detail/MeshIndexCheck.h"

namespace d2vdb {

void computeVertexNormals(TriangleMesh& mesh) {
  detail::checkTriangleIndices(mesh, "cannot compute vertex normals");
  std::vector<Eigen::Vector3d> sums(mesh.positions.size(), Eigen::Vector3d::Zero());
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    const Eigen::Vector3d a = mesh.positions[triangle[0]].cast<double>();
    const Eigen::Vector3d b = mesh.positions[triangle[1]].cast<double>();
    const Eigen::Vector3d c = mesh.positions[triangle[2]].cast<double>();
    // The cross product's length is twice the area, so adding it weights the unit normal by area.
    const Eigen::Vector3d areaWeightedNormal = (b - a).cross(c - a);
    for (const TriangleMesh::Index index : triangle) sums[index] += areaWeightedNormal;
  }
  std::vector<Eigen::Vector3f> normals(mesh.positions.size());
  for (std::size_t v = 0; v < sums.size(); ++v) {
    const double length = sums[v].norm();
    if (length > 0.0 && std::isfinite(length)) {
      normals[v] = (sums[v] / length).cast<float>();
    } else {
      normals[v] = Eigen::Vector3f::UnitZ();
    }
  }
  mesh.normals = std::move(normals);
}

}  // namespace d2vdb
