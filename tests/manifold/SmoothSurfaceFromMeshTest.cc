// smoothSurfaceFromMesh(): the smooth surface of an icosphere against the unit sphere, each source
// against the same construction made step by step, the early check and the messages.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "ManifoldTestSupport.h"
#include "common/ExpectInputError.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/PnTriangles.h"
#include "d2vdb/manifold/SmoothSurfaceFromMesh.h"
#include "d2vdb/manifold/SourceDistance.h"
#include "d2vdb/mesh/TriangleClosestPoint.h"

namespace d2vdb {
namespace {

/// The level-`levels` icosphere as a float mesh, with the sphere's own normals when asked.
TriangleMesh icosphereMesh(int levels, bool withNormals) {
  const test::UnitIcosphere sphere = test::unitIcosphere(levels);
  TriangleMesh mesh;
  for (const Eigen::Vector3d& p : sphere.positions) {
    mesh.positions.push_back(p.cast<float>());
    if (withNormals) mesh.normals.push_back(p.normalized().cast<float>());
  }
  mesh.triangles = sphere.triangles;
  return mesh;
}

/// Face points on the barycentric lattice with `samples` intervals per edge of every face.
std::vector<FacePoint> latticePoints(const HalfEdgeMesh& mesh, int samples) {
  std::vector<FacePoint> points;
  for (HalfEdgeMesh::Index face = 0; face < mesh.faceCount(); ++face) {
    for (const Eigen::Vector3d& bary : faceLattice(samples)) points.push_back({face, bary});
  }
  return points;
}

/// Largest | |X| - 1 | over the lattice points of every face: the distance to the unit sphere.
double distanceToUnitSphere(const MeshSmoothSurface& smooth) {
  double worst = 0.0;
  for (const FacePoint& point : latticePoints(*smooth.mesh, 6)) {
    worst = std::max(worst, std::abs(smooth.surface.position(point).norm() - 1.0));
  }
  return worst;
}

TEST(SmoothSurfaceFromMesh, PnTrianglesWithTheSpheresNormalsStayOnTheSphere) {
  // PN triangles interpolate the vertices and their normals, which are the sphere's: over the
  // level-3 icosphere (edges about 0.14) the patches stay within 1e-4 of the sphere.
  SmoothSurfaceFromMeshOptions options;
  options.source = SmoothSurfaceSource::PnTriangles;
  options.fileNormals = true;
  const MeshSmoothSurface smooth = smoothSurfaceFromMesh(icosphereMesh(3, true), options);
  EXPECT_TRUE(smooth.normalsFromFile);
  EXPECT_EQ(smooth.source->name(), "pn");
  EXPECT_EQ(smooth.subdividedFaces, 0u);
  EXPECT_EQ(smooth.mesh->faceCount(), 20u * 64u);
  const double distance = distanceToUnitSphere(smooth);
  std::printf("PN (sphere normals), icosphere 3: max | |X| - 1 | = %.3g\n", distance);
  EXPECT_LT(distance, 1e-4);
}

TEST(SmoothSurfaceFromMesh, LoopLimitSurfaceOfAnIcosphereLiesJustInsideTheSphere) {
  // Loop's masks are convex combinations, so the limit surface lies inside the convex hull of the
  // vertices, within the unit sphere; at a vertex of degree 6 the limit point is v / 2 plus 1/12
  // of each neighbour (Loop 1987), about (1 + cos theta) / 2 = 0.995 from the centre for the
  // level-3 icosphere's edges of theta = 0.138 rad.
  const MeshSmoothSurface smooth = smoothSurfaceFromMesh(icosphereMesh(3, false));
  EXPECT_EQ(smooth.source->name(), "loop");
  EXPECT_FALSE(smooth.normalsFromFile);
  // Level 3: no face has two degree-5 corners; the icosahedron: every face has three.
  EXPECT_EQ(smooth.subdividedFaces, 0u);
  EXPECT_EQ(smoothSurfaceFromMesh(icosphereMesh(0, false)).subdividedFaces, 20u);
  double lowest = 2.0, highest = 0.0;
  for (const FacePoint& point : latticePoints(*smooth.mesh, 6)) {
    const double radius = smooth.surface.position(point).norm();
    lowest = std::min(lowest, radius);
    highest = std::max(highest, radius);
  }
  std::printf("Loop, icosphere 3: radius %.6f .. %.6f\n", lowest, highest);
  EXPECT_LT(highest, 1.0);
  EXPECT_GT(lowest, 0.99);
  const HalfEdgeMesh& mesh = *smooth.mesh;
  double worst = 0.0;
  for (HalfEdgeMesh::Index v = 0; v < mesh.vertexCount(); ++v) {
    if (mesh.degree(v) != 6) continue;
    Eigen::Vector3d limit = 0.5 * mesh.position(v);
    for (int k = 0; k < 6; ++k) limit += mesh.position(mesh.to(mesh.ring(v, k))) / 12.0;
    const HalfEdgeMesh::Index h = mesh.ring(v, 0);
    FacePoint corner{HalfEdgeMesh::face(h), Eigen::Vector3d::Zero()};
    corner.bary[h % 3] = 1.0;
    worst = std::max(worst, (smooth.surface.position(corner) - limit).norm());
  }
  std::printf("Loop, icosphere 3: degree-6 vertices within %.3g of the limit mask\n", worst);
  EXPECT_LT(worst, 1e-4);
}

TEST(SmoothSurfaceFromMesh, DistanceToTheInputMeshIsTheBruteForceOneAndExceedsTheSourceDistance) {
  // PN triangles with the sphere's normals bulge out of the flat faces by about the sagitta
  // r^2 / 2 of their circumradius r; the distance to their own source is far smaller.
  const TriangleMesh input = icosphereMesh(2, true);
  SmoothSurfaceFromMeshOptions options;
  options.source = SmoothSurfaceSource::PnTriangles;
  options.fileNormals = true;
  const MeshSmoothSurface smooth = smoothSurfaceFromMesh(input, options);
  const MeshDistance distance(input);
  const MeshDeviationStatistics toMesh = distanceToMesh(smooth.surface, distance, 4);
  // Brute force: every lattice point against every triangle, in the same face order.
  double worst = 0.0, sumSquares = 0.0;
  std::size_t samples = 0;
  for (const FacePoint& point : latticePoints(*smooth.mesh, 4)) {
    const Eigen::Vector3d x = smooth.surface.position(point);
    double nearest = std::numeric_limits<double>::infinity();
    for (const TriangleMesh::Triangle& t : input.triangles) {
      const Eigen::Vector3d a = input.positions[t[0]].cast<double>();
      const Eigen::Vector3d b = input.positions[t[1]].cast<double>();
      const Eigen::Vector3d c = input.positions[t[2]].cast<double>();
      nearest = std::min(nearest, (closestPointOnTriangle(x, a, b, c).point - x).norm());
    }
    worst = std::max(worst, nearest);
    sumSquares += nearest * nearest;
    ++samples;
  }
  EXPECT_EQ(toMesh.samples, samples);
  EXPECT_EQ(toMesh.maxDistance, worst);
  EXPECT_NEAR(toMesh.rmsDistance, std::sqrt(sumSquares / static_cast<double>(samples)), 1e-15);
  const SourceDistanceStatistics toSource = distanceToSource(smooth.surface, *smooth.source, 4);
  std::printf("PN, icosphere 2: to the mesh max %.3g, to the source max %.3g\n", toMesh.maxDistance,
              toSource.maxDistance);
  EXPECT_GT(toMesh.maxDistance, 10.0 * toSource.maxDistance);
  // The level-2 icosphere's edges are about 0.3 long: circumradius about 0.18, sagitta 0.016.
  EXPECT_GT(toMesh.maxDistance, 0.005);
  EXPECT_LT(toMesh.maxDistance, 0.03);
  // One thread gives the same figures.
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const MeshDeviationStatistics serial = distanceToMesh(smooth.surface, distance, 4);
  EXPECT_EQ(serial.maxDistance, toMesh.maxDistance);
  EXPECT_EQ(serial.rmsDistance, toMesh.rmsDistance);
  test::expectInputError([&] { distanceToMesh(smooth.surface, distance, 0); }, {"sample"});
}

TEST(SmoothSurfaceFromMesh, IsTheStepByStepConstruction) {
  const TriangleMesh mesh = icosphereMesh(2, true);
  const auto halfEdges = std::make_shared<const HalfEdgeMesh>(mesh);
  PseudoManifoldOptions surfaceOptions;
  surfaceOptions.maxBidegree = 5;
  const LoopLimitSurface loop(halfEdges);
  const PnTriangles computedNormals(halfEdges);
  const PseudoManifold loopSurface(loop, surfaceOptions);
  const PseudoManifold pnSurface(computedNormals, surfaceOptions);

  SmoothSurfaceFromMeshOptions options;
  options.surface = surfaceOptions;
  const MeshSmoothSurface smoothLoop = smoothSurfaceFromMesh(mesh, options);
  options.source = SmoothSurfaceSource::PnTriangles;  // fileNormals false: computed normals
  const MeshSmoothSurface smoothPn = smoothSurfaceFromMesh(mesh, options);
  EXPECT_FALSE(smoothPn.normalsFromFile);
  for (const FacePoint& point : latticePoints(*halfEdges, 4)) {
    EXPECT_TRUE(smoothLoop.surface.position(point) == loopSurface.position(point));
    EXPECT_TRUE(smoothPn.surface.position(point) == pnSurface.position(point));
  }
  EXPECT_EQ(smoothLoop.surface.bidegree(0), 5);
}

TEST(SmoothSurfaceFromMesh, ChecksBeforeBuildingAndNamesTheMesh) {
  SmoothSurfaceFromMeshOptions options;
  std::size_t faces = 0;
  options.beforeBuilding = [&faces](const HalfEdgeMesh& mesh) { faces = mesh.faceCount(); };
  smoothSurfaceFromMesh(icosphereMesh(1, false), options);
  EXPECT_EQ(faces, 80u);
  options.beforeBuilding = [](const HalfEdgeMesh&) { throw std::runtime_error("refused"); };
  EXPECT_THROW(smoothSurfaceFromMesh(icosphereMesh(1, false), options), std::runtime_error);

  TriangleMesh open = icosphereMesh(1, false);
  open.triangles.pop_back();
  options.beforeBuilding = nullptr;
  options.label = "open.obj";
  test::expectInputError([&] { smoothSurfaceFromMesh(open, options); }, {"open.obj: "});
}

TEST(SmoothSurfaceFromMesh, SourceNames) {
  EXPECT_STREQ(smoothSurfaceSourceName(SmoothSurfaceSource::LoopLimit), "loop");
  EXPECT_STREQ(smoothSurfaceSourceName(SmoothSurfaceSource::PnTriangles), "pn");
}

}  // namespace
}  // namespace d2vdb
