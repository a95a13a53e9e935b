// Marching cubes on analytic level sets: topology (Euler characteristics), accuracy, offsets,
// ambiguous random data, determinism across thread counts, and the out-of-band diagnosis.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include "contour/ContourTestSupport.h"
#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/Primitives.h"

namespace d2vdb::test {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

openvdb::FloatGrid::Ptr sphereLevelSet(const Eigen::Vector3d& center, double radius,
                                       double voxelSize, double halfWidth = 3.0) {
  PrimitiveLevelSetOptions options;
  options.voxelSize = voxelSize;
  options.halfWidth = halfWidth;
  return primitiveLevelSet(Sphere(center, radius), options);
}

TEST(IsoSurface, SphereIsClosedGenusZeroWithOutwardNormals) {
  const Eigen::Vector3d center(0.3, -0.2, 0.15);
  const auto grid = sphereLevelSet(center, 12.0, 1.0);
  const TriangleMesh mesh = extractIsoSurface(*grid);
  expectClosedManifold(mesh, 2, "sphere");
  EXPECT_GT(signedVolume(mesh), 0.0);
  EXPECT_NEAR(signedVolume(mesh), 4.0 / 3.0 * M_PI * 12.0 * 12.0 * 12.0, 0.01 * 7238.0);
  ASSERT_TRUE(mesh.hasNormals());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3d radial = (mesh.positions[v].cast<double>() - center).normalized();
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
  const Eigen::Vector3d center(0.1, 0.2, 0.3);
  const DistanceFunction sphere = [&](const Eigen::Vector3d& p) {
    return (p - center).norm() - 2.0;
  };
  const auto grid =
      gridFromDistance<openvdb::DoubleGrid>(sphere, 0.25, 3.0, CoordBBox(Coord(-12), Coord(12)));
  const TriangleMesh mesh = extractIsoSurface(static_cast<const openvdb::GridBase&>(*grid));
  expectClosedManifold(mesh, 2, "double sphere");
}

TEST(IsoSurface, VerticesLieOnTheSphereOfRadiusFortyVoxels) {
  const double voxel = 0.5;
  const Eigen::Vector3d center(0.37, -0.21, 0.113);
  const auto grid = sphereLevelSet(center, 40.0 * voxel, voxel);
  for (const double isoVoxels : {0.0, 1.0, -1.0}) {
    IsoSurfaceOptions options;
    options.isoValue = isoVoxels * voxel;
    const TriangleMesh mesh = extractIsoSurface(*grid, options);
    expectClosedManifold(mesh, 2, "sphere at iso " + std::to_string(isoVoxels));
    const double radius = (40.0 + isoVoxels) * voxel;
    double worst = 0.0;
    for (const auto& position : mesh.positions) {
      worst = std::max(worst, std::abs((position.cast<double>() - center).norm() - radius));
    }
    EXPECT_LT(worst / voxel, 0.02) << "iso " << isoVoxels << " voxels";
  }
}

/// Sets the voxels of `box` to random values in [-1, 1], a tenth of them to the iso-value
/// exactly (many ambiguous faces and cells).
void addRandomValues(openvdb::FloatGrid& grid, unsigned seed, double iso, const CoordBBox& box) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  std::uniform_int_distribution<int> tenth(0, 9);
  auto accessor = grid.getAccessor();
  for (auto ijk = box.begin(); ijk; ++ijk) {
    const float v = value(random);
    accessor.setValue(*ijk, tenth(random) == 0 ? static_cast<float>(iso) : v);
  }
}

/// A FloatGrid of random values in a box, with an "outside" background.
openvdb::FloatGrid::Ptr randomBlock(unsigned seed, double iso) {
  auto grid = openvdb::FloatGrid::create(1.0f);
  addRandomValues(*grid, seed, iso, CoordBBox(Coord(-5, -3, -4), Coord(12, 10, 9)));
  return grid;
}

/// Brute-force reference: every grid edge with an end in an allocated leaf whose ends lie on
/// both sides of `iso`, keyed by (start voxel, axis), with the parameter of its vertex (linear
/// interpolation, kept kCornerClearance away from the ends).
std::map<std::array<int, 4>, double> crossedLeafEdges(const openvdb::FloatGrid& grid, double iso) {
  std::map<std::array<int, 4>, double> edges;
  const auto accessor = grid.getConstAccessor();
  for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
    for (auto voxel = leaf->cbeginValueAll(); voxel; ++voxel) {
      for (int axis = 0; axis < 3; ++axis) {
        for (const int step : {-1, 1}) {
          Coord start = voxel.getCoord(), end = start;
          (step > 0 ? end : start)[axis] += step;
          const double v0 = accessor.getValue(start), v1 = accessor.getValue(end);
          if ((v0 < iso) == (v1 < iso)) continue;
          edges[{start.x(), start.y(), start.z(), axis}] =
              std::clamp((iso - v0) / (v1 - v0), kCornerClearance, 1.0 - kCornerClearance);
        }
      }
    }
  }
  return edges;
}

TEST(IsoSurface, OneVertexOnEveryCrossedEdgeWhereverTheBlocksLie) {
  // Two boxes of random values, side by side and then far apart (a sparse set of blocks), with
  // an identity transform so that vertices are in index space.
  const double iso = 0.2;
  for (const int distance : {20, 3000}) {
    auto grid = openvdb::FloatGrid::create(1.0f);
    addRandomValues(*grid, 21, iso, CoordBBox(Coord(-5, -3, -4), Coord(12, 10, 9)));
    addRandomValues(*grid, 22, iso,
                    CoordBBox(Coord(distance - 5, 3, -20), Coord(distance + 9, 17, -7)));
    IsoSurfaceOptions options;
    options.isoValue = iso;
    options.computeNormals = false;
    const TriangleMesh mesh = extractIsoSurface(*grid, options);
    const std::string what = "distance " + std::to_string(distance);
    const MeshReport report = validateMesh(mesh);
    EXPECT_TRUE(report.closed && report.manifold && report.oriented)
        << what << ": " << report.problems();

    // A vertex with two integer coordinates lies on the edge from there along the third axis;
    // the others are the centre vertices of cells with 8- to 12-sided contours.
    const auto expected = crossedLeafEdges(*grid, iso);
    std::map<std::array<int, 4>, int> verticesOnEdge;
    std::size_t centerVertices = 0;
    for (const auto& position : mesh.positions) {
      std::array<int, 4> edge{0, 0, 0, -1};
      int integers = 0;
      for (int i = 0; i < 3; ++i) {
        edge[i] = static_cast<int>(std::floor(position[i]));
        if (position[i] == std::floor(position[i])) {
          ++integers;
        } else {
          edge[3] = i;
        }
      }
      if (integers != 2) {
        ++centerVertices;
        continue;
      }
      const auto found = expected.find(edge);
      ASSERT_NE(found, expected.end()) << what << ": a vertex on an edge that is not crossed";
      EXPECT_NEAR(position[edge[3]] - edge[edge[3]], found->second, 1e-3) << what;
      ++verticesOnEdge[edge];
    }
    EXPECT_EQ(verticesOnEdge.size(), expected.size()) << what << ": crossed edges without vertex";
    for (const auto& [edge, count] : verticesOnEdge) EXPECT_EQ(count, 1) << what;
    EXPECT_LT(centerVertices, expected.size() / 20) << what;
    // Every triangle lies in one cell.
    for (const auto& triangle : mesh.triangles) {
      for (int axis = 0; axis < 3; ++axis) {
        float low = mesh.positions[triangle[0]][axis], high = low;
        for (const auto vertex : triangle) {
          low = std::min(low, mesh.positions[vertex][axis]);
          high = std::max(high, mesh.positions[vertex][axis]);
        }
        EXPECT_LE(std::ceil(high) - std::floor(low), 1.0f) << what;
      }
    }

    TriangleMesh twoThreads;
    {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
      twoThreads = extractIsoSurface(*grid, options);
    }
    EXPECT_EQ(twoThreads.positions, mesh.positions) << what;
    EXPECT_EQ(twoThreads.triangles, mesh.triangles) << what;
  }
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

TEST(IsoSurface, ReportsProgressOfBothPassesFromTheCallingThread) {
  const auto sphere = sphereLevelSet(Eigen::Vector3d::Zero(), 6.0, 0.5);
  const auto empty = openvdb::FloatGrid::create(1.0f);
  for (const openvdb::FloatGrid* grid : {sphere.get(), empty.get()}) {
    std::vector<std::pair<std::string, double>> reports;
    const auto caller = std::this_thread::get_id();
    const ProgressCallback progress = [&](std::string_view stage, double fraction) {
      EXPECT_EQ(std::this_thread::get_id(), caller);
      reports.emplace_back(std::string(stage), fraction);
    };
    extractIsoSurface(*grid, {}, progress);
    ASSERT_FALSE(reports.empty());
    double previous = 0.0;
    for (std::size_t i = 0; i < reports.size(); ++i) {
      const auto& [stage, fraction] = reports[i];
      EXPECT_TRUE(stage == "contour: counting" || stage == "contour: meshing") << stage;
      EXPECT_TRUE(fraction >= 0.0 && fraction <= 1.0) << stage << " " << fraction;
      if (i > 0 && stage == reports[i - 1].first) {
        EXPECT_GE(fraction, previous) << stage;
      }
      previous = fraction;
    }
    EXPECT_EQ(reports.front().first, "contour: counting");
    EXPECT_EQ(reports.back().first, "contour: meshing");
    EXPECT_EQ(reports.back().second, 1.0);
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
