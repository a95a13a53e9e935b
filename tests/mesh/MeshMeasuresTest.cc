// Bounding boxes, surface areas and vertex normals against hand-computed values.
#include "d2vdb/mesh/MeshMeasures.h"

#include <gtest/gtest.h>

#include <cmath>

#include "d2vdb/mesh/VertexNormals.h"
#include "mesh/MeshTestSupport.h"

namespace {

using d2vdb::BoundingBox;
using d2vdb::TriangleMesh;
using d2vdb::test::cube;
using d2vdb::test::makeMesh;
using d2vdb::test::tetrahedron;

void expectVectorNear(const Eigen::Vector3f& actual, const Eigen::Vector3d& expected) {
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(actual[axis], expected[axis], 1e-6) << "axis " << axis;
  }
}

TEST(MeshMeasures, BoundingBoxOfReferencedVertices) {
  TriangleMesh mesh = cube(Eigen::Vector3f(-2.0f, 3.0f, 0.5f));
  mesh.positions.emplace_back(100.0f, -100.0f, 7.0f);  // used by no triangle: ignored
  const BoundingBox box = d2vdb::boundingBox(mesh);
  EXPECT_EQ(box.min, Eigen::Vector3d(-2.0, 3.0, 0.5));
  EXPECT_EQ(box.max, Eigen::Vector3d(-1.0, 4.0, 1.5));
  EXPECT_EQ(box.extent(), Eigen::Vector3d(1.0, 1.0, 1.0));
}

TEST(MeshMeasures, BoundingBoxOfPointsWithoutTriangles) {
  const TriangleMesh points = makeMesh({{1, 2, 3}, {-1, 5, 0}, {4, -2, 1}}, {});
  const BoundingBox box = d2vdb::boundingBox(points);
  EXPECT_EQ(box.min, Eigen::Vector3d(-1.0, -2.0, 0.0));
  EXPECT_EQ(box.max, Eigen::Vector3d(4.0, 5.0, 3.0));
}

TEST(MeshMeasures, BoundingBoxErrors) {
  d2vdb::test::expectInputError([] { d2vdb::boundingBox(TriangleMesh{}); }, {"without vertices"});
  const TriangleMesh bad = makeMesh({{0, 0, 0}}, {{0, 0, 3}});
  d2vdb::test::expectInputError([&] { d2vdb::boundingBox(bad); }, {"vertex 3"});
}

TEST(MeshMeasures, SurfaceArea) {
  EXPECT_NEAR(d2vdb::surfaceArea(cube()), 6.0, 1e-12);
  EXPECT_NEAR(d2vdb::surfaceArea(tetrahedron()), 1.5 + std::sqrt(3.0) / 2.0, 1e-12);
  // A 3-4-5 right triangle scaled by 1000: area 6e6.
  const TriangleMesh right = makeMesh({{0, 0, 0}, {3000, 0, 0}, {0, 4000, 0}}, {{0, 1, 2}});
  EXPECT_NEAR(d2vdb::surfaceArea(right), 6.0e6, 1e-6);
  EXPECT_EQ(d2vdb::surfaceArea(TriangleMesh{}), 0.0);
  const TriangleMesh bad = makeMesh({{0, 0, 0}}, {{0, 1, 0}});
  d2vdb::test::expectInputError([&] { d2vdb::surfaceArea(bad); }, {"vertex 1"});
}

TEST(VertexNormals, OctahedronNormalsPointAlongTheAxes) {
  // Each vertex of the octahedron is surrounded by four congruent faces symmetric about its axis.
  TriangleMesh mesh = makeMesh(
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
      {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
  d2vdb::computeVertexNormals(mesh);
  ASSERT_TRUE(mesh.hasNormals());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    expectVectorNear(mesh.normals[v], mesh.positions[v].cast<double>());
  }
}

TEST(VertexNormals, WeightsByAreaNotByAngle) {
  // At vertex 0 a right triangle of area 2 facing +z meets one of area 1/2 facing +y (both with
  // a 90 degree corner there), so the area-weighted normal is (0, 1, 4) / sqrt(17).
  TriangleMesh mesh =
      makeMesh({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 1}, {1, 0, 0}}, {{0, 1, 2}, {0, 3, 4}});
  d2vdb::computeVertexNormals(mesh);
  expectVectorNear(mesh.normals[0], Eigen::Vector3d(0, 1, 4) / std::sqrt(17.0));
  expectVectorNear(mesh.normals[1], Eigen::Vector3d(0, 0, 1));
  expectVectorNear(mesh.normals[3], Eigen::Vector3d(0, 1, 0));
}

TEST(VertexNormals, ZeroAreaAndUnusedVerticesGetPlusZ) {
  TriangleMesh mesh = makeMesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 5, 5}}, {{0, 1, 2}});
  d2vdb::computeVertexNormals(mesh);
  ASSERT_EQ(mesh.normals.size(), 4u);
  for (const Eigen::Vector3f& normal : mesh.normals) expectVectorNear(normal, {0, 0, 1});
}

TEST(VertexNormals, CubeNormalsAreUnitAndPointOutward) {
  TriangleMesh mesh = cube();
  d2vdb::computeVertexNormals(mesh);
  const Eigen::Vector3f center(0.5f, 0.5f, 0.5f);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    EXPECT_NEAR(mesh.normals[v].norm(), 1.0f, 1e-6f);
    // Each corner's normal has a positive component along each of its three outward face axes.
    const Eigen::Vector3f outward = mesh.positions[v] - center;
    for (int axis = 0; axis < 3; ++axis) EXPECT_GT(mesh.normals[v][axis] * outward[axis], 0.0f);
  }
}

TEST(VertexNormals, BadIndexLeavesMeshUnchanged) {
  TriangleMesh mesh = makeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 7}});
  d2vdb::test::expectInputError([&] { d2vdb::computeVertexNormals(mesh); }, {"vertex 7"});
  EXPECT_TRUE(mesh.normals.empty());
}

}  // namespace
