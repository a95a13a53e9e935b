// surfaceGenus() on meshes whose genus is known by construction: spheres (a tetrahedron, a cube),
// a torus, polycube slabs with 1..3 tunnels, disjoint unions, and meshes that have no genus.
#include "d2vdb/mesh/MeshGenus.h"

#include <gtest/gtest.h>

#include <optional>

#include "field/PolycubeMeshes.h"
#include "mesh/MeshTestSupport.h"

namespace {

using d2vdb::MeshReport;
using d2vdb::surfaceGenus;
using d2vdb::TriangleMesh;
using d2vdb::validateMesh;
using d2vdb::test::append;
using d2vdb::test::cube;
using d2vdb::test::tetrahedron;
using d2vdb::test::torus;

std::optional<long> genusOf(const TriangleMesh& mesh) {
  return surfaceGenus(validateMesh(mesh));
}

TEST(MeshGenus, SpheresHaveGenusZeroAndTheTorusOne) {
  EXPECT_EQ(genusOf(tetrahedron()), 0);
  EXPECT_EQ(genusOf(cube()), 0);
  EXPECT_EQ(genusOf(torus(24, 12)), 1);
}

TEST(MeshGenus, PolycubeWithTunnelsHasOneGenusPerTunnel) {
  for (int tunnels = 0; tunnels <= 3; ++tunnels) {
    d2vdb::test::PolycubeSpec spec;
    spec.genus = tunnels;
    spec.seed = static_cast<std::uint32_t>(5 + tunnels);
    EXPECT_EQ(genusOf(d2vdb::test::makePolycubeMesh(spec)), tunnels) << tunnels;
  }
}

TEST(MeshGenus, DisjointUnionsAddTheGenera) {
  TriangleMesh sphereAndTorus = cube(Eigen::Vector3f(10, 0, 0));
  append(sphereAndTorus, torus(24, 12));
  EXPECT_EQ(genusOf(sphereAndTorus), 1);  // chi = 2 + 0, two components

  TriangleMesh twoTori = torus(24, 12);
  TriangleMesh shifted = torus(16, 8);
  for (Eigen::Vector3f& position : shifted.positions) position.x() += 10.0f;
  append(twoTori, shifted);
  EXPECT_EQ(genusOf(twoTori), 2);  // chi = 0, two components

  TriangleMesh threeSpheres = tetrahedron();
  append(threeSpheres, cube(Eigen::Vector3f(3, 0, 0)));
  append(threeSpheres, cube(Eigen::Vector3f(6, 0, 0)));
  EXPECT_EQ(genusOf(threeSpheres), 0);  // chi = 6, three components
}

TEST(MeshGenus, OpenNonManifoldOrUnorientedMeshesHaveNone) {
  TriangleMesh open = cube();
  open.triangles.pop_back();
  EXPECT_FALSE(d2vdb::isClosedOrientedManifold(validateMesh(open)));
  EXPECT_EQ(genusOf(open), std::nullopt);

  TriangleMesh flipped = cube();
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  EXPECT_FALSE(d2vdb::isClosedOrientedManifold(validateMesh(flipped)));
  EXPECT_EQ(genusOf(flipped), std::nullopt);

  // Two cubes glued along one edge: that edge has four triangles.
  TriangleMesh glued = cube();
  append(glued, cube(Eigen::Vector3f(1, 1, 0)));
  ASSERT_EQ(genusOf(glued), 0);  // apart (no shared vertex yet): two spheres
  // Weld the second cube's corners (0, 0, z) + (1, 1, 0) onto the first cube's (1, 1, z).
  for (TriangleMesh::Triangle& triangle : glued.triangles) {
    for (auto& vertex : triangle) {
      if (vertex == 8 + 0) vertex = 2;  // (1, 1, 0)
      if (vertex == 8 + 4) vertex = 6;  // (1, 1, 1)
    }
  }
  const MeshReport welded = validateMesh(glued);
  EXPECT_FALSE(welded.manifold);
  EXPECT_EQ(surfaceGenus(welded), std::nullopt);

  EXPECT_TRUE(d2vdb::isClosedOrientedManifold(validateMesh(torus(24, 12))));
}

}  // namespace
