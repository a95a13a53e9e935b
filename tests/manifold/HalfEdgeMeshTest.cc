// Half-edge adjacency: rings counter-clockwise, twins, degrees; refusal of meshes that are not
// closed, consistently oriented 2-manifolds, with the offending edges or vertices named.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <limits>
#include <string>

#include "ManifoldTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/HalfEdgeMesh.h"
#include "d2vdb/manifold/LoopSubdivision.h"

namespace d2vdb {
namespace {

using test::DoubleMesh;
using Index = HalfEdgeMesh::Index;

std::string errorOf(const DoubleMesh& m) {
  try {
    HalfEdgeMesh mesh(m.positions, m.triangles);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(HalfEdgeMesh, RingsAreCounterClockwiseAndTwinsMatch) {
  for (const DoubleMesh& m : {test::octahedron(), test::icosphere(1), test::mixedDegreeMesh()}) {
    const auto mesh = m.build();
    EXPECT_EQ(mesh->halfEdgeCount(), 3 * m.triangles.size());
    std::vector<int> expectedDegrees = test::degrees(m);
    for (Index v = 0; v < mesh->vertexCount(); ++v) {
      ASSERT_EQ(mesh->degree(v), expectedDegrees[v]);
      const Eigen::Vector3d& center = mesh->position(v);
      for (int k = 0; k < mesh->degree(v); ++k) {
        const Index h = mesh->ring(v, k);
        EXPECT_EQ(mesh->from(h), v);
        EXPECT_EQ(mesh->ringIndex(h), k);
        EXPECT_EQ(mesh->twin(mesh->twin(h)), h);
        EXPECT_EQ(mesh->from(mesh->twin(h)), mesh->to(h));
        EXPECT_EQ(mesh->to(mesh->twin(h)), v);
        // The face of ring k is (v, n_k, n_{k+1}), counter-clockwise seen from outside (the
        // meshes are star-shaped around the origin).
        const Index next = mesh->ring(v, k + 1);
        EXPECT_EQ(HalfEdgeMesh::face(h), HalfEdgeMesh::face(HalfEdgeMesh::prev(mesh->twin(next))));
        const Eigen::Vector3d a = mesh->position(mesh->to(h)) - center;
        const Eigen::Vector3d b = mesh->position(mesh->to(next)) - center;
        EXPECT_GT(a.cross(b).dot(center), 0.0);
      }
      // The ring starts with the outgoing half-edge of smallest index.
      for (int k = 1; k < mesh->degree(v); ++k) EXPECT_LT(mesh->ring(v, 0), mesh->ring(v, k));
    }
  }
}

TEST(HalfEdgeMesh, RefusesAnOpenMeshNamingBoundaryEdges) {
  DoubleMesh m = test::octahedron();
  m.triangles.pop_back();  // the last face {0, 3, 5} (possibly reoriented) leaves a hole
  const std::string message = errorOf(m);
  EXPECT_TRUE(contains(message, "3 boundary edges in 1 loop")) << message;
  EXPECT_TRUE(contains(message, "(0, 3), (0, 5), (3, 5)")) << message;
}

TEST(HalfEdgeMesh, RefusesNonManifoldEdges) {
  DoubleMesh m = test::tetrahedron();
  // A fin: one more triangle on the edge (0, 1).
  m.positions.emplace_back(3.0, 0.0, 0.0);
  m.triangles.push_back({0, 1, 4});
  const std::string message = errorOf(m);
  EXPECT_TRUE(contains(message, "non-manifold edge")) << message;
  EXPECT_TRUE(contains(message, "(0, 1)")) << message;
}

TEST(HalfEdgeMesh, RefusesInconsistentOrientation) {
  DoubleMesh m = test::octahedron();
  std::swap(m.triangles[0][1], m.triangles[0][2]);
  const std::string message = errorOf(m);
  EXPECT_TRUE(contains(message, "3 inconsistently oriented edges")) << message;
  const auto& t = m.triangles[0];
  const std::string first =
      "(" + std::to_string(std::min(t[0], t[1])) + ", " + std::to_string(std::max(t[0], t[1]));
  EXPECT_TRUE(contains(message, "3 edges without exactly one opposite half-edge")) << message;
}

TEST(HalfEdgeMesh, RefusesAVertexWithTwoFans) {
  // Two tetrahedra sharing vertex 0 only.
  DoubleMesh a = test::tetrahedron();
  DoubleMesh m = a;
  for (int i = 1; i < 4; ++i) m.positions.push_back(a.positions[i] + Eigen::Vector3d(0, 0, 5));
  for (TriangleMesh::Triangle t : a.triangles) {
    for (auto& v : t) {
      if (v != 0) v += 3;
    }
    m.triangles.push_back(t);
  }
  const std::string message = errorOf(m);
  EXPECT_TRUE(contains(message, "1 vertex whose triangles form more than one fan, the first 0"))
      << message;
  EXPECT_TRUE(contains(message, "non-manifold vertex")) << message;
}

TEST(HalfEdgeMesh, RefusesDegenerateInput) {
  DoubleMesh empty;
  EXPECT_TRUE(contains(errorOf(empty), "no triangles"));
  DoubleMesh repeated = test::tetrahedron();
  repeated.triangles[2] = {1, 1, 2};
  EXPECT_TRUE(contains(errorOf(repeated), "triangle 2 repeats a vertex"));
  DoubleMesh badIndex = test::tetrahedron();
  badIndex.triangles[1][2] = 9;
  EXPECT_TRUE(contains(errorOf(badIndex), "references vertex 9"));
  DoubleMesh nan = test::tetrahedron();
  nan.positions[2].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(contains(errorOf(nan), "vertex 2 has a non-finite coordinate"));
  // Two triangles folded onto each other: closed and oriented, but degree 2 everywhere.
  DoubleMesh pillow;
  pillow.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  pillow.triangles = {{0, 1, 2}, {0, 2, 1}};
  EXPECT_TRUE(contains(errorOf(pillow), "fewer than three neighbours"));
}

TEST(HalfEdgeMesh, UnusedVerticesKeepTheirIndices) {
  DoubleMesh m = test::octahedron();
  m.positions.emplace_back(9.0, 9.0, 9.0);
  const HalfEdgeMesh mesh(m.positions, m.triangles);
  EXPECT_EQ(mesh.vertexCount(), 7u);
  EXPECT_EQ(mesh.degree(6), 0);
  EXPECT_NEAR(mesh.boundingBoxDiagonal(), 2.0 * std::sqrt(3.0), 1e-15);
}

TEST(LoopSubdivision, MatchesThePlainReference) {
  const DoubleMesh m = test::mixedDegreeMesh();
  const HalfEdgeMesh fine = loopSubdivision(*m.build());
  const DoubleMesh reference = test::referenceSubdivide(m);
  ASSERT_EQ(fine.faceCount(), reference.triangles.size());
  // Same faces by position (vertex numbering may differ for edge points).
  for (std::size_t f = 0; f < reference.triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = fine.position(fine.corner(static_cast<Index>(f), k));
      const Eigen::Vector3d b = reference.positions[reference.triangles[f][k]];
      EXPECT_LT((a - b).norm(), 1e-15);
    }
  }
}

}  // namespace
}  // namespace d2vdb
