// The level-set way of offsetting: what loadOffsetLevelSet() takes, the voxel budget of the moving
// band against the bound written out here, and offsets of a sphere's exact level set against the
// offset sphere |x - c| = R + d.
#include "d2vdb/io/LevelSetOffsets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/Icosphere.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"
#include "io/IoTestSupport.h"

namespace d2vdb {
namespace {

using Eigen::Vector3d;
using test::expectInputError;

const Vector3d kCenter(0.2, -0.1, 0.05);
constexpr double kRadius = 1.0;
constexpr double kVoxel = 0.05;

openvdb::FloatGrid::Ptr sphereLevelSet() {
  return primitiveLevelSet(Sphere(kCenter, kRadius), {kVoxel, 3.0});
}

// The largest deviation of the mesh's vertices from the sphere of radius `radius` about kCenter.
double sphereError(const TriangleMesh& mesh, double radius) {
  double worst = 0.0;
  for (const Eigen::Vector3f& p : mesh.positions) {
    worst = std::max(worst, std::abs((p.cast<double>() - kCenter).norm() - radius));
  }
  return worst;
}

class LevelSetOffsetsTest : public test::ScratchDirectoryTest {};

TEST_F(LevelSetOffsetsTest, LoadsALevelSetOrConvertsAClosedMesh) {
  writeVdb(file("sphere.vdb"), {sphereLevelSet()});
  const OffsetLevelSet levelSet = loadOffsetLevelSet(file("sphere.vdb"), {});
  EXPECT_EQ(levelSet.kind, InputKind::LevelSet);
  ASSERT_TRUE(levelSet.grid);
  EXPECT_DOUBLE_EQ(levelSet.grid->voxelSize()[0], kVoxel);
  EXPECT_TRUE(levelSet.warnings.empty());

  const test::UnitIcosphere sphere = test::unitIcosphere(3);
  TriangleMesh mesh;
  for (const Vector3d& p : sphere.positions) mesh.positions.push_back(p.cast<float>());
  mesh.triangles = sphere.triangles;
  writeMesh(file("sphere.stl"), mesh);
  LevelSetOptions options;
  options.voxelSize = 0.04;
  const OffsetLevelSet converted = loadOffsetLevelSet(file("sphere.stl"), options);
  EXPECT_EQ(converted.kind, InputKind::Mesh);
  ASSERT_TRUE(converted.grid);
  EXPECT_DOUBLE_EQ(converted.grid->voxelSize()[0], 0.04);
  EXPECT_GT(converted.grid->activeVoxelCount(), 0u);

  write("points.xyz", "0 0 0\n1 0 0\n");
  expectInputError([&] { loadOffsetLevelSet(file("points.xyz"), {}); },
                   {"is a point set (.xyz); the input of 'd2vdb offset --method levelset'"});
  write("vertices.ply",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n1 0 0\n");
  expectInputError([&] { loadOffsetLevelSet(file("vertices.ply"), {}); },
                   {"has no triangles: the level-set method needs a closed mesh or a level set"});
}

TEST_F(LevelSetOffsetsTest, BudgetBoundsTheGrownBandsVoxels) {
  const openvdb::FloatGrid::Ptr grid = sphereLevelSet();
  // The bound: the area of the active voxels' bounding box grown by 2 max(d, 0), in voxels, times
  // the band's width 2 halfWidth, with a margin of 1.25.
  const openvdb::Vec3d side = grid->evalActiveVoxelBoundingBox().dim().asVec3d() * kVoxel;
  const auto bound = [&](double d) {
    const double g = std::max(0.0, 2.0 * d);
    const double x = side.x() + g, y = side.y() + g, z = side.z() + g;
    return 2.0 * (x * y + y * z + z * x) / (kVoxel * kVoxel) * 2.0 * 3.0 * 1.25;
  };
  const auto between = static_cast<std::uint64_t>(0.5 * (bound(0.0) + bound(1.0)));
  checkLevelSetOffsetBudget(*grid, {-0.5, 0.0}, 3.0, between);  // inward offsets do not grow
  expectInputError(
      [&] {
        checkLevelSetOffsetBudget(*grid, {0.0, 1.0}, 3.0, between);
      },
      {"offsetting by 1 at voxel size 0.05 would need about " +
       std::to_string(static_cast<long long>(bound(1.0))) + " active voxels, above --max-voxels " +
       std::to_string(between)});
}

TEST_F(LevelSetOffsetsTest, BudgetBoundsTheVoxelUpdatesOfLongMoves) {
  const openvdb::FloatGrid::Ptr grid = sphereLevelSet();
  // Within the voxel budget (2^40) but 2 |d| / voxel = 4,000 steps over the grown band: refused
  // before anything moves, naming the method that offsets exactly at any distance.
  expectInputError([&] { checkLevelSetOffsetBudget(*grid, {100.0}, 3.0, std::uint64_t{1} << 40); },
                   {"offsetting by 100 at voxel size 0.05 moves the band in 4000 half-voxel steps",
                    "use --method support"});
  checkLevelSetOffsetBudget(*grid, {0.5, -0.5}, 3.0, std::uint64_t{1} << 40);
}

TEST_F(LevelSetOffsetsTest, OffsetsOfASphereAreTheOffsetSpheres) {
  const openvdb::FloatGrid::Ptr grid = sphereLevelSet();
  const openvdb::Index64 before = grid->activeVoxelCount();
  for (const double d : {0.2, -0.3}) {
    const LevelSetOffset offset = offsetLevelSet(*grid, d, "sphere.vdb");
    ASSERT_TRUE(offset.grid);
    EXPECT_NE(offset.grid.get(), grid.get());
    ASSERT_GT(offset.mesh.triangles.size(), 1000u);
    EXPECT_TRUE(offset.mesh.hasNormals());
    EXPECT_LT(sphereError(offset.mesh, kRadius + d), 0.2 * kVoxel) << "d = " << d;
  }
  EXPECT_EQ(grid->activeVoxelCount(), before);  // the input is left as it was
  expectInputError([&] { offsetLevelSet(*grid, -1.2, "sphere.vdb"); },
                   {"the offset at distance -1.2 of 'sphere.vdb' is empty (the body is thinner "
                    "than 2 |d|)"});
}

}  // namespace
}  // namespace d2vdb
