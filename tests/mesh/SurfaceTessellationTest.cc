#include "d2vdb/mesh/SurfaceTessellation.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "d2vdb/core/Error.h"

namespace {

using d2vdb::BSplineSurface;
using d2vdb::KnotVector;
using d2vdb::TriangleMesh;
using Eigen::Vector3d;

Vector3d geometricNormal(const TriangleMesh& mesh, const TriangleMesh::Triangle& triangle) {
  const Vector3d p0 = mesh.positions[triangle[0]].cast<double>();
  const Vector3d p1 = mesh.positions[triangle[1]].cast<double>();
  const Vector3d p2 = mesh.positions[triangle[2]].cast<double>();
  return (p1 - p0).cross(p2 - p0);
}

// A wavy open bicubic patch over [0, 3] x [0, 2] in x, y.
BSplineSurface wavyPatch() {
  const int nu = 6;
  const int nv = 5;
  std::vector<Vector3d> points;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      points.emplace_back(3.0 * i / (nu - 1), 2.0 * j / (nv - 1), 0.4 * std::sin(i + 2.0 * j));
    }
  }
  return BSplineSurface::clamped(3, 3, nu, nv, points);
}

// A torus-like surface closed in both directions: control grid on a torus (R =
// 3, r = 1).
BSplineSurface torus() {
  const int nu = 8;
  const int nv = 6;
  std::vector<Vector3d> points;
  for (int i = 0; i < nu; ++i) {
    const double theta = 2.0 * M_PI * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double phi = 2.0 * M_PI * j / nv;
      const double radius = 3.0 + std::cos(phi);
      points.emplace_back(radius * std::cos(theta), radius * std::sin(theta), std::sin(phi));
    }
  }
  return BSplineSurface(KnotVector::periodic(3, nu), KnotVector::periodic(2, nv), points, true,
                        true);
}

TEST(SurfaceTessellation, VerticesAndNormalsSampleTheSurfaceOnTheDocumentedGrid) {
  const BSplineSurface surface = wavyPatch();
  const int samplesU = 7;
  const int samplesV = 5;
  const TriangleMesh mesh = d2vdb::tessellate(surface, samplesU, samplesV);
  ASSERT_EQ(mesh.vertexCount(), 35u);
  ASSERT_EQ(mesh.triangleCount(), 2u * 6 * 4);
  ASSERT_TRUE(mesh.hasNormals());
  for (int i = 0; i < samplesU; ++i) {
    for (int j = 0; j < samplesV; ++j) {
      const double u = i / 6.0;
      const double v = j / 4.0;
      const d2vdb::SurfaceDerivatives d = surface.derivatives(u, v);
      const std::size_t index = static_cast<std::size_t>(i * samplesV + j);
      EXPECT_LT((mesh.positions[index].cast<double>() - d.point).norm(), 1e-6);
      const Vector3d expected = d.du.cross(d.dv).normalized();
      EXPECT_LT((mesh.normals[index].cast<double>() - expected).norm(), 1e-6);
      EXPECT_NEAR(mesh.normals[index].norm(), 1.0f, 1e-6f);
    }
  }
}

TEST(SurfaceTessellation, PlanarPatchIsWoundCounterClockwiseAroundSuCrossSv) {
  // u along x, v along y: Su x Sv = +z, so every triangle is counter-clockwise
  // seen from +z.
  std::vector<Vector3d> points;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) points.emplace_back(i, 0.5 * j * j, 0.0);
  }
  const TriangleMesh mesh = d2vdb::tessellate(BSplineSurface::clamped(2, 3, 3, 4, points), 4, 6);
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    const Vector3d normal = geometricNormal(mesh, triangle);
    EXPECT_GT(normal.z(), 0.0);
    EXPECT_NEAR(normal.x(), 0.0, 1e-6);
    EXPECT_NEAR(normal.y(), 0.0, 1e-6);
  }
  for (const Eigen::Vector3f& normal : mesh.normals) EXPECT_EQ(normal, Eigen::Vector3f(0, 0, 1));
}

TEST(SurfaceTessellation, TriangleOrientationAgreesWithVertexNormals) {
  const TriangleMesh mesh = d2vdb::tessellate(wavyPatch(), 30, 25);
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    const Vector3d normal = geometricNormal(mesh, triangle).normalized();
    for (const TriangleMesh::Index index : triangle) {
      EXPECT_GT(normal.dot(mesh.normals[index].cast<double>()), 0.9);
    }
  }
}

TEST(SurfaceTessellation, DoublyClosedSurfaceGivesAClosedConsistentlyOrientedTorus) {
  const int samplesU = 24;
  const int samplesV = 16;
  const TriangleMesh mesh = d2vdb::tessellate(torus(), samplesU, samplesV);
  EXPECT_EQ(mesh.vertexCount(), static_cast<std::size_t>(samplesU * samplesV));
  EXPECT_EQ(mesh.triangleCount(), static_cast<std::size_t>(2 * samplesU * samplesV));
  // Each directed edge appears once and its reverse once: closed and
  // consistently oriented.
  std::map<std::pair<TriangleMesh::Index, TriangleMesh::Index>, int> directed;
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{triangle[k], triangle[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    const auto reverse = directed.find({edge.second, edge.first});
    ASSERT_NE(reverse, directed.end());
    EXPECT_EQ(reverse->second, 1);
  }
  // Euler characteristic of a torus: V - E + F = 0.
  const long edges = static_cast<long>(directed.size()) / 2;
  EXPECT_EQ(static_cast<long>(mesh.vertexCount()) - edges + static_cast<long>(mesh.triangleCount()),
            0);
  // The seam vertices sample the surface at the domain start (no duplicate at
  // the end).
  EXPECT_LT((mesh.positions[0].cast<double>() - torus().evaluate(0.0, 0.0)).norm(), 1e-6);
  // Normals: all on the same side (outward or inward) relative to the tube's
  // centre circle.
  int outward = 0;
  for (std::size_t index = 0; index < mesh.vertexCount(); ++index) {
    const Vector3d p = mesh.positions[index].cast<double>();
    const Vector3d center = 3.0 * Vector3d(p.x(), p.y(), 0.0).normalized();
    if ((p - center).dot(mesh.normals[index].cast<double>()) > 0.0) ++outward;
  }
  EXPECT_TRUE(outward == 0 || outward == static_cast<int>(mesh.vertexCount())) << outward;
}

TEST(SurfaceTessellation, PoleVerticesGetTheNormalOfTheirTriangles) {
  // A half dome over a half disc: row 0 collapses to the apex (0, 0, 1), so Sv
  // vanishes there. Row 1 lies at the apex height, so the surface has the
  // tangent plane z = 1 at the apex (a smooth pole rather than a cone point).
  const int nu = 4;
  const int nv = 5;
  std::vector<Vector3d> points;
  for (int i = 0; i < nu; ++i) {
    const double radius = static_cast<double>(i) / (nu - 1);
    const double height = i <= 1 ? 1.0 : 1.0 - radius * radius;
    for (int j = 0; j < nv; ++j) {
      const double angle = M_PI * j / (nv - 1);
      points.emplace_back(radius * std::cos(angle), radius * std::sin(angle), height);
    }
  }
  const BSplineSurface dome = BSplineSurface::clamped(2, 2, nu, nv, points);
  EXPECT_TRUE(dome.derivatives(0.0, 0.5).dv.isZero(1e-12));
  const TriangleMesh mesh = d2vdb::tessellate(dome, 20, 11);
  // u runs outward from the apex and v counter-clockwise seen from above, so Su
  // x Sv points up; the apex normal is the limit (0, 0, 1) for every copy of
  // the apex.
  EXPECT_GT(mesh.normals[11 + 5].z(), 0.0f);
  for (int j = 0; j < 11; ++j) {
    const Eigen::Vector3f normal = mesh.normals[static_cast<std::size_t>(j)];
    EXPECT_LT((normal - Eigen::Vector3f(0, 0, 1)).norm(), 1e-4f) << j;
  }
}

TEST(SurfaceTessellation, ResultDoesNotDependOnTheThreadCount) {
  const BSplineSurface surface = torus();
  TriangleMesh serial;
  {
    const tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    serial = d2vdb::tessellate(surface, 64, 48);
  }
  const TriangleMesh parallel = d2vdb::tessellate(surface, 64, 48);
  EXPECT_EQ(serial.positions, parallel.positions);
  EXPECT_EQ(serial.normals, parallel.normals);
  EXPECT_EQ(serial.triangles, parallel.triangles);
}

TEST(SurfaceTessellation, RejectsTooFewSamplesAndFullyDegenerateSurfaces) {
  EXPECT_THROW(d2vdb::tessellate(wavyPatch(), 1, 5), d2vdb::InputError);
  EXPECT_THROW(d2vdb::tessellate(wavyPatch(), 5, 1), d2vdb::InputError);
  EXPECT_THROW(d2vdb::tessellate(torus(), 2, 5), d2vdb::InputError);
  EXPECT_NO_THROW(d2vdb::tessellate(torus(), 3, 3));
  const BSplineSurface point =
      BSplineSurface::clamped(1, 1, 2, 2, std::vector<Vector3d>(4, Vector3d(1.0, 2.0, 3.0)));
  EXPECT_THROW(d2vdb::tessellate(point, 4, 4), d2vdb::InputError);
}

}  // namespace
