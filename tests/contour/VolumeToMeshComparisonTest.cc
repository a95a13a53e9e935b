// Our mesh of the bunny against openvdb::tools::volumeToMesh's: within half a voxel of each other
// (two-sided, sampled at every vertex of each mesh through a fine distance field of the other).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/VolumeToMesh.h>

#include "contour/ContourTestSupport.h"
#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/mesh/MeshIO.h"

namespace d2vdb::test {
namespace {

TriangleMesh openVdbMesh(const openvdb::FloatGrid& grid) {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(grid, points, triangles, quads, 0.0, 0.0);
  TriangleMesh mesh;
  for (const auto& p : points) mesh.positions.emplace_back(p[0], p[1], p[2]);
  for (const auto& t : triangles) mesh.triangles.push_back({t[0], t[1], t[2]});
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  }
  return mesh;
}

/// |distance| from each vertex of `mesh` to the surface whose level set is `field`, sorted.
std::vector<double> sampledDistances(const TriangleMesh& mesh, const openvdb::FloatGrid& field) {
  const openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(field);
  std::vector<double> distances;
  distances.reserve(mesh.vertexCount());
  for (const auto& p : mesh.positions) {
    distances.push_back(
        std::abs(static_cast<double>(sampler.wsSample(openvdb::Vec3d(p.x(), p.y(), p.z())))));
  }
  std::sort(distances.begin(), distances.end());
  return distances;
}

TEST(IsoSurfaceComparison, BunnyAgreesWithVolumeToMesh) {
  const TriangleMesh bunny =
      readMesh(std::filesystem::path(D2VDB_SOURCE_DIR) / "volumes" / "bunny.obj");
  LevelSetOptions options;
  options.resolution = 128;
  const openvdb::FloatGrid::Ptr grid = meshToLevelSet(bunny, options).grid;
  const double voxel = grid->voxelSize()[0];

  const TriangleMesh ours = extractIsoSurface(*grid);
  const TriangleMesh theirs = openVdbMesh(*grid);
  const MeshReport report = validateMesh(ours);
  EXPECT_TRUE(report.closed && report.manifold && report.oriented) << report.problems();
  EXPECT_EQ(report.degenerateTriangleCount, 0u);

  LevelSetOptions fieldOptions;
  fieldOptions.voxelSize = voxel / 4;  // fine enough that trilinear sampling adds little error
  const auto ourField = meshToLevelSet(ours, fieldOptions).grid;
  const auto theirField = meshToLevelSet(theirs, fieldOptions).grid;
  // Our vertices lie on the grid's trilinear zero set; volumeToMesh's dual vertices (one per
  // cell, averaged edge crossings) cut corners at sharp features, where a handful of our vertices
  // end up just over half a voxel from its quads. Hence: 99.9% of the samples on either side
  // within 0.5 voxel, every sample within 0.6 voxel.
  const auto onGrid = sampledDistances(ours, *grid);
  EXPECT_LT(onGrid.back() / voxel, 0.01);
  for (const auto& distances :
       {sampledDistances(ours, *theirField), sampledDistances(theirs, *ourField)}) {
    EXPECT_LT(distances[distances.size() * 999 / 1000] / voxel, 0.5);
    EXPECT_LT(distances.back() / voxel, 0.6);
  }
}

}  // namespace
}  // namespace d2vdb::test
