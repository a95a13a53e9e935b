// Marching cubes on analytic level sets: topology (Euler characteristics), accuracy, offsets,
// ambiguous random data, determinism across thread counts, and the out-of-band diagnosis.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>
#include <string>

#include "contour/ContourTestSupport.h"
#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/Primitives.h"

namespace d2vdb::test {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

openvdb::FloatGrid::Ptr sphereLevelSet(const Eigen::Vector3d& centre, double radius,
                                       double voxelSize, double halfWidth = 3.0) {
  PrimitiveLevelSetOptions options;
  options.voxelSize = voxelSize;
  options.halfWidth = halfWidth;
  return primitiveLevelSet(Sphere(centre, radius), options);
}

TEST(IsoSurface, SphereIsClosedGenusZeroWithOutwardNormals) {
  const Eigen::Vector3d centre(0.3, -0.2, 0.15);
  const auto grid = sphereLevelSet(centre, 12.0, 1.0);
  const TriangleMesh mesh = extractIsoSurface(*grid);
  expectClosedManifold(mesh, 2, "sphere");
  EXPECT_GT(signedVolume(mesh), 0.0);
  EXPECT_NEAR(signedVolume(mesh), 4.0 / 3.0 * M_PI * 12.0 * 12.0 * 12.0, 0.01 * 7238.0);
  ASSERT_TRUE(mesh.hasNormals());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3d radial = (mesh.positions[v].cast<double>() - centre).normalized();
    EXPECT_GT(radial.dot(mesh.normals[v].cast<double>()), 0.995) << "vertex " << v;
    EXPECT_NEAR(mesh.normals[v].norm(), 1.0, 1e-5);
  }
}

TEST(IsoSurface, TorusHasEulerCharacteristicZero) {
  const Torus torus(Eigen::Vector3d(0.5, 0.25, -0.3), 3.0, 1.0);
  PrimitiveLevelSetOptions options;
  options.voxelSize = 0.1;
  const TriangleMesh mesh = extractIsoSurface(*primitiveLevelSet(torus, options));
  expectClosedManifold(mesh, 0, "torus");
  EXPECT_GT(signedVolume(mesh), 0.0);
}

TEST(IsoSurface, TwoFusedToriHaveGenusTwo) {
  const Eigen::Vector3d left(-10.0, 0.0, 0.0), right(10.0, 0.0, 0.0);
  const DistanceFunction genusTwo = [&](const Eigen::Vector3d& p) {
    return std::min(torusDistance(p, left, 12.0, 4.0), torusDistance(p, right, 12.0, 4.0));
  };
  const auto grid = gridFromDistance<openvdb::FloatGrid>(
      genusTwo, 0.7, 3.0, CoordBBox(Coord(-50, -30, -12), Coord(50, 30, 12)));
  const TriangleMesh mesh = extractIsoSurface(*grid);
  expectClosedManifold(mesh, -2, "two fused tori");
}

TEST(IsoSurface, DoubleGridSphere) {
  const Eigen::Vector3d centre(0.1, 0.2, 0.3);
  const DistanceFunction sphere = [&](const Eigen::Vector3d& p) {
    return (p - centre).norm() - 2.0;
  };
  const auto grid =
      gridFromDistance<openvdb::DoubleGrid>(sphere, 0.25, 3.0, CoordBBox(Coord(-12), Coord(12)));
  const TriangleMesh mesh = extractIsoSurface(static_cast<const openvdb::GridBase&>(*grid));
  expectClosedManifold(mesh, 2, "double sphere");
}

TEST(IsoSurface, VerticesLieOnTheSphereOfRadiusFortyVoxels) {
  const double voxel = 0.5;
  const Eigen::Vector3d centre(0.37, -0.21, 0.113);
  const auto grid = sphereLevelSet(centre, 40.0 * voxel, voxel);
  for (const double isoVoxels : {0.0, 1.0, -1.0}) {
    IsoSurfaceOptions options;
    options.isoValue = isoVoxels * voxel;
    const TriangleMesh mesh = extractIsoSurface(*grid, options);
    expectClosedManifold(mesh, 2, "sphere at iso " + std::to_string(isoVoxels));
    const double radius = (40.0 + isoVoxels) * voxel;
    double worst = 0.0;
    for (const auto& position : mesh.positions) {
      worst = std::max(worst, std::abs((position.cast<double>() - centre).norm() - radius));
    }
    EXPECT_LT(worst / voxel, 0.02) << "iso " << isoVoxels << " voxels";
  }
}

/// A FloatGrid of random values in a box (many ambiguous faces and cells), with an "outside"
/// background; a tenth of the values equal the iso-value exactly.
openvdb::FloatGrid::Ptr randomBlock(unsigned seed, double iso) {
  auto grid = openvdb::FloatGrid::create(1.0f);
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  std::uniform_int_distribution<int> tenth(0, 9);
  auto accessor = grid->getAccessor();
  for (auto ijk = CoordBBox(Coord(-5, -3, -4), Coord(12, 10, 9)).begin(); ijk; ++ijk) {
    const float v = value(random);
    accessor.setValue(*ijk, tenth(random) == 0 ? static_cast<float>(iso) : v);
  }
  return grid;
}

TEST(IsoSurface, RandomValuesGiveClosedManifoldMeshes) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    for (const double iso : {0.0, 0.3, -0.45}) {
      const auto grid = randomBlock(seed, iso);
      IsoSurfaceOptions options;
      options.isoValue = iso;
      const TriangleMesh mesh = extractIsoSurface(*grid, options);
      const std::string what = "seed " + std::to_string(seed) + " iso " + std::to_string(iso);
      const MeshReport report = validateMesh(mesh);
      EXPECT_TRUE(report.closed) << what << ": " << report.problems();
      EXPECT_TRUE(report.manifold) << what << ": " << report.problems();
      EXPECT_TRUE(report.oriented) << what << ": " << report.problems();
      EXPECT_EQ(report.degenerateTriangleCount, 0u) << what;
      EXPECT_EQ(report.unreferencedVertexCount, 0u) << what;

      options.raw = true;
      const TriangleMesh raw = extractIsoSurface(*grid, options);
      const MeshReport rawReport = validateMesh(raw);
      EXPECT_EQ(raw.triangles, mesh.triangles) << what;
      EXPECT_TRUE(rawReport.closed && rawReport.manifold && rawReport.oriented) << what;
    }
  }
}

TEST(IsoSurface, SameOutputForOneAndTwoThreads) {
  const auto sphere = sphereLevelSet(Eigen::Vector3d(0.1, 0.2, 0.3), 9.0, 0.25);
  const auto random = randomBlock(11, 0.1);
  for (const openvdb::FloatGrid* grid : {sphere.get(), random.get()}) {
    IsoSurfaceOptions options;
    options.isoValue = grid == random.get() ? 0.1 : 0.0;
    TriangleMesh one, two;
    {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
      one = extractIsoSurface(*grid, options);
    }
    {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
      two = extractIsoSurface(*grid, options);
    }
    EXPECT_EQ(one.positions, two.positions);
    EXPECT_EQ(one.normals, two.normals);
    EXPECT_EQ(one.triangles, two.triangles);
  }
}

TEST(IsoSurface, ReportsIsoValuesBeyondTheBand) {
  const auto grid = sphereLevelSet(Eigen::Vector3d::Zero(), 8.0, 0.5, 3.0);
  IsoSurfaceOptions options;
  options.isoValue = 1.0;  // two voxels: the limit of a three-voxel band
  EXPECT_NO_THROW(extractIsoSurface(*grid, options));
  options.isoValue = -1.2;
  try {
    extractIsoSurface(*grid, options);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("exceeds by 0.2"), std::string::npos) << message;
    EXPECT_NE(message.find("up to about 1"), std::string::npos) << message;
  }
  options.isoValue = std::nan("");
  EXPECT_THROW(extractIsoSurface(*grid, options), InputError);
}

TEST(IsoSurface, ReportsSurfacesLeavingTheStoredLeaves) {
  // A solid leaf beside a solid tile of the same value: the surface around the tile is not
  // stored in any leaf, so the mesh would be open.
  auto grid = openvdb::FloatGrid::create(1.0f);
  grid->tree().addTile(1, Coord(8, 0, 0), -1.0f, false);
  grid->tree().touchLeaf(Coord(0, 0, 0))->fill(-1.0f);
  try {
    extractIsoSurface(*grid);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("leaves the stored band"), std::string::npos)
        << error.what();
  }
}

TEST(IsoSurface, EmptyWhenNothingCrosses) {
  const auto grid = sphereLevelSet(Eigen::Vector3d::Zero(), 4.0, 1.0);
  IsoSurfaceOptions options;
  const auto empty = openvdb::FloatGrid::create(1.0f);
  EXPECT_EQ(extractIsoSurface(*empty, options).triangleCount(), 0u);
  const auto integers = openvdb::Int32Grid::create(0);
  EXPECT_THROW(extractIsoSurface(static_cast<const openvdb::GridBase&>(*integers)), InputError);
}

}  // namespace
}  // namespace d2vdb::test
