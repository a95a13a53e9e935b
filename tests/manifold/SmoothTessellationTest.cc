// Tessellation of a pseudo-manifold: closed, manifold, oriented (watertight by construction),
// the expected counts, vertices on the surface with its normals and curvatures.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "ManifoldTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/SmoothTessellation.h"
#include "d2vdb/mesh/MeshValidation.h"

namespace d2vdb {
namespace {

TEST(SmoothTessellation, ClosedManifoldOrientedWithTheExpectedCounts) {
  const test::DoubleMesh m = test::mixedDegreeMesh();
  const auto mesh = m.build();
  const LoopLimitSurface loop(mesh);
  const PseudoManifold pps(loop);
  const std::size_t edges = mesh->halfEdgeCount() / 2;
  for (const int levels : {0, 1, 3}) {
    const SmoothTessellation t = tessellateSmooth(pps, levels, levels == 1);
    const long g = 1L << levels;
    EXPECT_EQ(t.mesh.triangles.size(), mesh->faceCount() * static_cast<std::size_t>(g * g));
    EXPECT_EQ(t.mesh.positions.size(),
              mesh->vertexCount() + edges * static_cast<std::size_t>(g - 1) +
                  mesh->faceCount() * static_cast<std::size_t>((g - 1) * (g - 2) / 2));
    const MeshReport report = validateMesh(t.mesh);
    EXPECT_TRUE(report.closed) << report.problems();
    EXPECT_TRUE(report.manifold) << report.problems();
    EXPECT_TRUE(report.oriented) << report.problems();
    EXPECT_EQ(report.eulerCharacteristic, 2);
    EXPECT_EQ(report.degenerateTriangleCount, 0u);
    for (std::size_t i = 0; i < t.mesh.positions.size(); i += 7) {
      const SmoothPoint p = pps.evaluate(t.where[i], Derivatives::Second);
      EXPECT_EQ(t.mesh.positions[i], p.position.cast<float>());
      EXPECT_EQ(t.mesh.normals[i], p.normal.cast<float>());
      if (levels == 1) {
        EXPECT_EQ(t.k1[i], p.k1);
        EXPECT_EQ(t.k2[i], p.k2);
      }
    }
    // Triangles face the way the surface's normals point.
    for (const auto& tri : t.mesh.triangles) {
      const Eigen::Vector3f a = t.mesh.positions[tri[0]];
      const Eigen::Vector3f n = (t.mesh.positions[tri[1]] - a).cross(t.mesh.positions[tri[2]] - a);
      EXPECT_GT(n.dot(t.mesh.normals[tri[0]] + t.mesh.normals[tri[1]] + t.mesh.normals[tri[2]]),
                0.0f);
    }
  }
}

TEST(SmoothTessellation, RefusesTooManyTriangles) {
  const auto mesh = test::octahedron().build();
  const LoopLimitSurface loop(mesh);
  const PseudoManifold pps(loop);
  EXPECT_THROW(tessellateSmooth(pps, 11, false), InputError);
  EXPECT_THROW(tessellateSmooth(pps, -1, false), InputError);
  try {
    tessellateSmooth(pps, 4, false, 1000);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("2048 triangles"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace d2vdb
