// validateMesh on hand-built meshes whose topology is known exactly.
#include "d2vdb/mesh/MeshValidation.h"

#include <gtest/gtest.h>

#include "mesh/MeshTestSupport.h"

namespace {

using d2vdb::MeshReport;
using d2vdb::TriangleMesh;
using d2vdb::validateMesh;
using d2vdb::test::append;
using d2vdb::test::cube;
using d2vdb::test::makeMesh;
using d2vdb::test::tetrahedron;
using d2vdb::test::torus;

bool contains(const std::string& text, const std::string& fragment) {
  return text.find(fragment) != std::string::npos;
}

/// Two squares in the z = 0 plane that touch only at the vertex (1, 1, 0) (index 2).
TriangleMesh squaresTouchingAtACorner() {
  return makeMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}},
                  {{0, 1, 2}, {0, 2, 3}, {2, 4, 5}, {2, 5, 6}});
}

TEST(MeshValidation, TetrahedronIsClosedManifoldOrientedSphere) {
  const MeshReport report = validateMesh(tetrahedron());
  EXPECT_EQ(report.vertexCount, 4u);
  EXPECT_EQ(report.triangleCount, 4u);
  EXPECT_EQ(report.edgeCount, 6u);
  EXPECT_EQ(report.boundaryEdgeCount, 0u);
  EXPECT_EQ(report.boundaryLoopCount, 0u);
  EXPECT_EQ(report.nonManifoldEdgeCount, 0u);
  EXPECT_EQ(report.nonManifoldVertexCount, 0u);
  EXPECT_EQ(report.degenerateTriangleCount, 0u);
  EXPECT_EQ(report.inconsistentlyOrientedEdgeCount, 0u);
  EXPECT_EQ(report.unreferencedVertexCount, 0u);
  EXPECT_EQ(report.connectedComponentCount, 1u);
  EXPECT_EQ(report.eulerCharacteristic, 2);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.manifold);
  EXPECT_TRUE(report.oriented);
  EXPECT_EQ(report.problems(), "");
}

TEST(MeshValidation, CubeOfTwelveTriangles) {
  const MeshReport report = validateMesh(cube());
  EXPECT_EQ(report.vertexCount, 8u);
  EXPECT_EQ(report.triangleCount, 12u);
  EXPECT_EQ(report.edgeCount, 18u);  // 12 cube edges + 6 face diagonals
  EXPECT_EQ(report.eulerCharacteristic, 2);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.manifold);
  EXPECT_TRUE(report.oriented);
  EXPECT_EQ(report.connectedComponentCount, 1u);
  EXPECT_EQ(report.problems(), "");
}

TEST(MeshValidation, OpenSquareHasOneLoopOfFourEdges) {
  const MeshReport report =
      validateMesh(makeMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}));
  EXPECT_EQ(report.edgeCount, 5u);
  EXPECT_EQ(report.boundaryEdgeCount, 4u);
  EXPECT_EQ(report.boundaryLoopCount, 1u);
  EXPECT_EQ(report.eulerCharacteristic, 1);  // a disc
  EXPECT_FALSE(report.closed);
  EXPECT_TRUE(report.manifold);
  EXPECT_TRUE(report.oriented);
  EXPECT_EQ(report.problems(), "4 boundary edges in 1 loop (the mesh is not closed)\n");
}

TEST(MeshValidation, OpenSquareWithAFlippedTriangleStillHasOneLoop) {
  const MeshReport report =
      validateMesh(makeMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 3, 2}}));
  EXPECT_EQ(report.boundaryEdgeCount, 4u);
  EXPECT_EQ(report.boundaryLoopCount, 1u);
  EXPECT_EQ(report.inconsistentlyOrientedEdgeCount, 1u);  // the diagonal 0-2
  EXPECT_FALSE(report.oriented);
}

TEST(MeshValidation, SquareWithSquareHoleHasTwoLoops) {
  // A 4x4 vertex grid of 3x3 cells with the middle cell left out: an annulus.
  TriangleMesh mesh;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) mesh.positions.emplace_back(float(i), float(j), 0.0f);
  }
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      if (i == 1 && j == 1) continue;
      const auto v = static_cast<TriangleMesh::Index>(4 * j + i);
      mesh.triangles.push_back({v, v + 1, v + 5});
      mesh.triangles.push_back({v, v + 5, v + 4});
    }
  }
  const MeshReport report = validateMesh(mesh);
  EXPECT_EQ(report.boundaryEdgeCount, 16u);  // 12 outside, 4 around the hole
  EXPECT_EQ(report.boundaryLoopCount, 2u);
  EXPECT_EQ(report.eulerCharacteristic, 0);  // 16 - 32 + 16
  EXPECT_TRUE(report.manifold);
  EXPECT_EQ(report.connectedComponentCount, 1u);
}

TEST(MeshValidation, TwoTetrahedraSharingAnEdgeHaveANonManifoldEdge) {
  // Vertices 0 and 1 belong to both tetrahedra; the second uses 4 and 5 as its other corners.
  TriangleMesh mesh = tetrahedron();
  mesh.positions.emplace_back(0.0f, -1.0f, 0.0f);
  mesh.positions.emplace_back(0.0f, 0.0f, -1.0f);
  // Same combinatorial pattern as tetrahedron() with 2 -> 4 and 3 -> 5 (consistently oriented).
  for (const TriangleMesh::Triangle& triangle : tetrahedron().triangles) {
    TriangleMesh::Triangle mapped = triangle;
    for (TriangleMesh::Index& index : mapped) index = index == 2 ? 4 : index == 3 ? 5 : index;
    mesh.triangles.push_back(mapped);
  }
  const MeshReport report = validateMesh(mesh);
  EXPECT_EQ(report.edgeCount, 11u);
  EXPECT_EQ(report.nonManifoldEdgeCount, 1u);  // edge 0-1, used by four triangles
  EXPECT_EQ(report.boundaryEdgeCount, 0u);
  EXPECT_EQ(report.nonManifoldVertexCount, 0u);  // the fans are joined through edge 0-1
  EXPECT_EQ(report.connectedComponentCount, 1u);
  EXPECT_EQ(report.eulerCharacteristic, 3);  // 6 - 11 + 8
  EXPECT_FALSE(report.closed);
  EXPECT_FALSE(report.manifold);
  EXPECT_TRUE(contains(report.problems(), "1 non-manifold edge ")) << report.problems();
}

TEST(MeshValidation, FlippedTriangleMakesItsThreeEdgesInconsistent) {
  TriangleMesh mesh = tetrahedron();
  std::swap(mesh.triangles[3][1], mesh.triangles[3][2]);
  const MeshReport report = validateMesh(mesh);
  EXPECT_EQ(report.inconsistentlyOrientedEdgeCount, 3u);
  EXPECT_FALSE(report.oriented);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.manifold);
  EXPECT_EQ(report.problems(),
            "3 inconsistently oriented edges (neighbouring triangles wound in opposite "
            "directions)\n");
}

TEST(MeshValidation, TwoCubesSharingOneVertexHaveANonManifoldVertex) {
  TriangleMesh mesh = cube();
  const TriangleMesh second = cube(Eigen::Vector3f(1, 1, 1));
  // The second cube's corner 0 is the first cube's corner 6, (1,1,1); its others are new.
  for (std::size_t v = 1; v < second.positions.size(); ++v) {
    mesh.positions.push_back(second.positions[v]);
  }
  for (const TriangleMesh::Triangle& triangle : second.triangles) {
    TriangleMesh::Triangle mapped{};
    for (std::size_t k = 0; k < 3; ++k) {
      mapped[k] = triangle[k] == 0 ? 6 : triangle[k] + 7;
    }
    mesh.triangles.push_back(mapped);
  }
  const MeshReport report = validateMesh(mesh);
  EXPECT_EQ(report.vertexCount, 15u);
  EXPECT_EQ(report.nonManifoldVertexCount, 1u);
  EXPECT_EQ(report.nonManifoldEdgeCount, 0u);
  EXPECT_EQ(report.connectedComponentCount, 2u);  // edge-connected components
  EXPECT_EQ(report.eulerCharacteristic, 3);       // 15 - 36 + 24
  EXPECT_TRUE(report.closed);
  EXPECT_FALSE(report.manifold);
  EXPECT_TRUE(report.oriented);
  EXPECT_TRUE(contains(report.problems(), "1 non-manifold vertex ")) << report.problems();
}

TEST(MeshValidation, SquaresTouchingAtACornerKeepTwoBoundaryLoops) {
  const MeshReport report = validateMesh(squaresTouchingAtACorner());
  EXPECT_EQ(report.boundaryEdgeCount, 8u);
  EXPECT_EQ(report.boundaryLoopCount, 2u);
  EXPECT_EQ(report.nonManifoldVertexCount, 1u);
  EXPECT_EQ(report.connectedComponentCount, 2u);
}

TEST(MeshValidation, BoundaryLoopsDoNotDependOnTriangleOrder) {
  TriangleMesh mesh = squaresTouchingAtACorner();
  std::reverse(mesh.triangles.begin(), mesh.triangles.end());
  EXPECT_EQ(validateMesh(mesh).boundaryLoopCount, 2u);
  // Bow tie: two single triangles meeting at vertex 0.
  const MeshReport bowTie = validateMesh(
      makeMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}}, {{0, 1, 2}, {0, 3, 4}}));
  EXPECT_EQ(bowTie.boundaryEdgeCount, 6u);
  EXPECT_EQ(bowTie.boundaryLoopCount, 2u);
  EXPECT_EQ(bowTie.nonManifoldVertexCount, 1u);
}

TEST(MeshValidation, DegenerateTriangles) {
  TriangleMesh mesh = tetrahedron();
  mesh.positions.emplace_back(0.5f, 0.0f, 0.0f);   // 4: on edge 0-1
  mesh.triangles.push_back({0, 4, 1});             // zero area
  mesh.triangles.push_back({2, 2, 3});             // repeated index
  mesh.positions.emplace_back(0.0f, 0.0f, 5.0f);   // 5
  mesh.positions.emplace_back(1e-4f, 0.0f, 5.0f);  // 6
  mesh.positions.emplace_back(0.0f, 1e-4f, 5.0f);  // 7: |cross| = 1e-8, far above 1e-12*scale
  mesh.triangles.push_back({5, 6, 7});
  const MeshReport report = validateMesh(mesh);
  EXPECT_EQ(report.degenerateTriangleCount, 2u);
  EXPECT_TRUE(contains(report.problems(), "2 degenerate triangles")) << report.problems();
  // The repeated-index triangle adds no edges: 6 + 2 (0-4, 4-1) + 3 (small triangle).
  EXPECT_EQ(report.edgeCount, 11u);
  EXPECT_EQ(report.nonManifoldEdgeCount, 1u);  // edge 0-1 now has three triangles
}

TEST(MeshValidation, ClosedTorusHasEulerCharacteristicZero) {
  const MeshReport report = validateMesh(torus(24, 12));
  EXPECT_EQ(report.vertexCount, 288u);
  EXPECT_EQ(report.edgeCount, 3u * 288u);
  EXPECT_EQ(report.eulerCharacteristic, 0);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.manifold);
  EXPECT_TRUE(report.oriented);
  EXPECT_EQ(report.degenerateTriangleCount, 0u);
  EXPECT_EQ(report.problems(), "");
}

TEST(MeshValidation, ComponentsAndUnreferencedVertices) {
  TriangleMesh mesh = tetrahedron();
  append(mesh, cube(Eigen::Vector3f(5, 0, 0)));
  mesh.positions.emplace_back(100.0f, 100.0f, 100.0f);
  mesh.positions.emplace_back(-100.0f, 0.0f, 0.0f);
  const MeshReport report = validateMesh(mesh);
  EXPECT_EQ(report.connectedComponentCount, 2u);
  EXPECT_EQ(report.unreferencedVertexCount, 2u);
  EXPECT_EQ(report.eulerCharacteristic, 4);  // two spheres; unreferenced vertices not counted
  EXPECT_TRUE(report.closed);
  EXPECT_EQ(report.problems(), "");
}

TEST(MeshValidation, EmptyMeshIsNotClosed) {
  const MeshReport report = validateMesh(TriangleMesh{});
  EXPECT_EQ(report.triangleCount, 0u);
  EXPECT_FALSE(report.closed);
  EXPECT_TRUE(contains(report.problems(), "no triangles")) << report.problems();
}

TEST(MeshValidation, OutOfRangeIndexIsInputError) {
  TriangleMesh mesh = tetrahedron();
  mesh.triangles.push_back({0, 1, 4});
  d2vdb::test::expectInputError([&] { validateMesh(mesh); },
                                {"triangle 4", "vertex 4", "4 vertices"});
}

TEST(MeshValidation, LargeTorusIsHandled) {
  // 400 x 300 grid: 240000 triangles, closed genus-one surface.
  const MeshReport report = validateMesh(torus(400, 300));
  EXPECT_EQ(report.triangleCount, 240000u);
  EXPECT_EQ(report.edgeCount, 360000u);
  EXPECT_EQ(report.eulerCharacteristic, 0);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.manifold);
  EXPECT_TRUE(report.oriented);
  EXPECT_EQ(report.connectedComponentCount, 1u);
}

}  // namespace
