// Helpers of ContourTestSupport.h (the only test file that instantiates flood filling).
#include "contour/ContourTestSupport.h"

#include <openvdb/tools/SignedFloodFill.h>

#include <cmath>

namespace d2vdb::test {

template <typename GridT>
typename GridT::Ptr gridFromDistance(const DistanceFunction& distance, double voxelSize,
                                     double halfWidth, const openvdb::CoordBBox& bounds) {
  using ValueT = typename GridT::ValueType;
  const double background = halfWidth * voxelSize;
  auto grid = GridT::create(static_cast<ValueT>(background));
  grid->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  auto accessor = grid->getAccessor();
  for (auto ijk = bounds.begin(); ijk; ++ijk) {
    const Eigen::Vector3d point = voxelSize * Eigen::Vector3d((*ijk).x(), (*ijk).y(), (*ijk).z());
    const double d = distance(point);
    if (std::abs(d) < background) accessor.setValue(*ijk, static_cast<ValueT>(d));
  }
  openvdb::tools::signedFloodFill(grid->tree());
  return grid;
}

template openvdb::FloatGrid::Ptr gridFromDistance<openvdb::FloatGrid>(const DistanceFunction&,
                                                                      double, double,
                                                                      const openvdb::CoordBBox&);
template openvdb::DoubleGrid::Ptr gridFromDistance<openvdb::DoubleGrid>(const DistanceFunction&,
                                                                        double, double,
                                                                        const openvdb::CoordBBox&);

double torusDistance(const Eigen::Vector3d& point, const Eigen::Vector3d& center, double major,
                     double minor) {
  const Eigen::Vector3d local = point - center;
  const double ring = std::hypot(local.x(), local.y()) - major;
  return std::hypot(ring, local.z()) - minor;
}

void expectClosedManifold(const TriangleMesh& mesh, long eulerCharacteristic,
                          const std::string& what) {
  const MeshReport report = validateMesh(mesh);
  EXPECT_GT(report.triangleCount, 0u) << what;
  EXPECT_TRUE(report.closed) << what << ": " << report.problems();
  EXPECT_TRUE(report.manifold) << what << ": " << report.problems();
  EXPECT_TRUE(report.oriented) << what << ": " << report.problems();
  EXPECT_EQ(report.boundaryEdgeCount, 0u) << what;
  EXPECT_EQ(report.nonManifoldEdgeCount, 0u) << what;
  EXPECT_EQ(report.nonManifoldVertexCount, 0u) << what;
  EXPECT_EQ(report.degenerateTriangleCount, 0u) << what;
  EXPECT_EQ(report.unreferencedVertexCount, 0u) << what;
  EXPECT_EQ(report.eulerCharacteristic, eulerCharacteristic) << what;
}

double signedVolume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (const auto& triangle : mesh.triangles) {
    const Eigen::Vector3d a = mesh.positions[triangle[0]].cast<double>();
    const Eigen::Vector3d b = mesh.positions[triangle[1]].cast<double>();
    const Eigen::Vector3d c = mesh.positions[triangle[2]].cast<double>();
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

}  // namespace d2vdb::test
