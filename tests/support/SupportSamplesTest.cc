#include "d2vdb/support/SupportSamples.h"

#include <gtest/gtest.h>

#include "SupportTestSupport.h"
#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

TriangleMesh sphereMesh(int subdivisions, bool withNormals) {
  const SphericalTriangulation sphere = geodesicSphere(subdivisions);
  TriangleMesh mesh;
  for (const Eigen::Vector3d& n : sphere.normals) {
    mesh.positions.push_back((2.0 * n).cast<float>());
    if (withNormals) mesh.normals.push_back(n.cast<float>());
  }
  for (const auto& t : sphere.triangles) mesh.triangles.push_back({t[0], t[1], t[2]});
  return mesh;
}

TEST(SupportSamples, ClosedConvexMeshHasAnOrientationPreservingGaussImage) {
  const MeshGaussImage image = meshGaussImage(sphereMesh(2, true), "sphere");
  EXPECT_TRUE(image.closed);
  EXPECT_EQ(image.preservingTriangles, 320u);
  EXPECT_EQ(image.reversingTriangles, 0u);
  EXPECT_EQ(image.collapsedTriangles, 0u);
  EXPECT_TRUE(coversWholeSphere(image.gaussImage));
  ASSERT_EQ(image.samples.points.size(), 162u);
  EXPECT_LT((image.samples.points[5] - 2.0 * image.samples.normals[5]).norm(), 1e-6);
}

TEST(SupportSamples, MissingNormalsAreComputedAndUnusedVerticesSkipped) {
  TriangleMesh mesh = sphereMesh(1, false);
  mesh.positions.push_back(Eigen::Vector3f(9, 9, 9));  // used by no triangle
  const OrientedSamples samples = samplesFromMesh(mesh, "sphere");
  ASSERT_EQ(samples.points.size(), 42u);
  for (std::size_t i = 0; i < samples.points.size(); ++i) {
    // Area-weighted normals of an icosphere point nearly radially.
    EXPECT_GT(samples.normals[i].dot(samples.points[i].normalized()), 0.99);
  }
  TriangleMesh points;
  points.positions = {Eigen::Vector3f(1, 0, 0)};
  EXPECT_THROW(samplesFromMesh(points, "points"), InputError);  // a point set needs normals
  EXPECT_THROW(samplesFromMesh(TriangleMesh{}, "empty"), InputError);
  EXPECT_THROW(meshGaussImage(points, "points"), InputError);  // no triangles
}

TEST(SupportSamples, CheckNormalizesAndCountsUnnormalizedNormals) {
  OrientedSamples samples;
  samples.points = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0)};
  samples.normals = {Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(0, 1.0000001, 0)};
  const SampleCheck check = checkOrientedSamples(samples, "two");
  EXPECT_EQ(check.renormalized, 1u);
  EXPECT_NEAR(check.largestDeviation, 1.0, 1e-15);
  EXPECT_NEAR(samples.normals[0].norm(), 1.0, 1e-15);
  EXPECT_NEAR(samples.normals[1].norm(), 1.0, 1e-15);
  // Huge normals keep their direction (no overflow to infinity in the norm).
  samples.normals[0] = Eigen::Vector3d(3e200, 4e200, 0);
  checkOrientedSamples(samples, "two");
  EXPECT_LT((samples.normals[0] - Eigen::Vector3d(0.6, 0.8, 0)).norm(), 1e-15);
  samples.normals[1] = Eigen::Vector3d::Zero();
  EXPECT_THROW(checkOrientedSamples(samples, "two"), InputError);
}

}  // namespace
}  // namespace d2vdb
