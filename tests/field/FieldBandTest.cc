// Fields built from per-voxel approximants (FieldBand.h, ApproximantField::fromBand), the path a
// target with an exact closest-point projection takes: a band found from seeds on an analytic
// torus against brute force, its records against the torus, its level set's signs; a band over an
// existing grid's voxels; determinism; refusals.
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/field/FieldBand.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "ApproximantFieldTestSupport.h"
#include "FieldTestSupport.h"
#include "common/ExactApproximant.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/Primitives.h"

namespace d2vdb {
namespace {

using test::bandCenters;
using test::expectSameAnswers;
using test::randomPoints;
using test::withThreads;

/// The approximant of an analytic shape at `center`: its exact closest-point data.
template <typename Shape>
Approximant exactApproximant(const Shape& shape, const Eigen::Vector3d& center) {
  return test::approximantFrom(shape.closestSurfacePoint(center), center);
}

/// Points on the torus (centre, radii R and r, axis z) spaced at most `spacing` apart.
std::vector<Eigen::Vector3d> torusSeeds(const Eigen::Vector3d& center, double R, double r,
                                        double spacing) {
  const int around = static_cast<int>(std::ceil(2.0 * kPi * (R + r) / spacing));
  const int across = static_cast<int>(std::ceil(2.0 * kPi * r / spacing));
  std::vector<Eigen::Vector3d> seeds;
  for (int i = 0; i < around; ++i) {
    const double u = 2.0 * kPi * i / around;
    for (int j = 0; j < across; ++j) {
      const double v = 2.0 * kPi * j / across;
      seeds.push_back(center + Eigen::Vector3d((R + r * std::cos(v)) * std::cos(u),
                                               (R + r * std::cos(v)) * std::sin(u),
                                               r * std::sin(v)));
    }
  }
  return seeds;
}

/// The torus field the way a smooth-surface target would build it: seeds on the surface, the
/// exact projection at every voxel centre.
/// Seeds 0.7 voxel apart along both circles: every point of the torus lies within about 0.5
/// voxel of one (`seedReach`, voxels, is passed on to nearSeeds).
ApproximantField exactTorusField(const Torus& torus, double R, double r, double h,
                                 double seedReach = 1.5) {
  FieldBand band = FieldBand::nearSeeds(
      TargetKind::Surface, torusSeeds(torus.center(), R, r, 0.7 * h), h, 3.0, seedReach);
  band.setApproximants([&](const openvdb::Coord&, const Eigen::Vector3d& center) {
        return exactApproximant(torus, center);
      })
      .setEstimator("exact projection onto the torus")
      .setLabel("analytic torus");
  return ApproximantField::fromBand(band);
}

TEST(FieldBand, NearSeedsSurfaceFromAnExactProjection) {
  const double h = 0.03, R = 0.9, r = 0.3;
  const Torus torus(Eigen::Vector3d(0.02, -0.01, 0.005), R, r);
  const ApproximantField field = exactTorusField(torus, R, r, h);
  EXPECT_EQ(field.kind(), TargetKind::Surface);
  EXPECT_EQ(field.estimator(), "exact projection onto the torus");
  EXPECT_EQ(field.halfWidth(), 3.0);
  const openvdb::FloatGrid& grid = *field.distanceGrid();
  EXPECT_EQ(grid.getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(grid.getName(), "surface");

  // The band is exactly the voxels within 3 voxels of the torus (brute force over its box).
  std::set<std::tuple<int, int, int>> expected, actual;
  const int reach = static_cast<int>(std::ceil((R + r) / h)) + 5;
  const int height = static_cast<int>(std::ceil(r / h)) + 5;
  for (int i = -reach; i <= reach; ++i) {
    for (int j = -reach; j <= reach; ++j) {
      for (int k = -height; k <= height; ++k) {
        if (std::abs(torus.signedDistance(Eigen::Vector3d(i, j, k) * h)) < 3.0 * h) {
          expected.emplace(i, j, k);
        }
      }
    }
  }
  for (auto voxel = grid.cbeginValueOn(); voxel; ++voxel) {
    const openvdb::Coord c = voxel.getCoord();
    actual.emplace(c.x(), c.y(), c.z());
  }
  EXPECT_EQ(actual.size(), expected.size());
  EXPECT_TRUE(actual == expected);

  // The records hold the projection's data up to their quantisation.
  double distanceError = 0.0, normalError = 0.0, curvatureError = 0.0, e1Error = 0.0;
  ApproximantField::Accessor accessor(field);
  for (const Eigen::Vector3d& center : bandCenters(field)) {
    const Approximant a = accessor.approximantAt(center);
    const SurfacePoint s = torus.closestSurfacePoint(center);
    distanceError = std::max(distanceError, std::abs(a.distance - s.signedDistance) / h);
    normalError = std::max(normalError, test::lineAngleDegrees(a.normal, s.normal));
    curvatureError =
        std::max({curvatureError, std::abs(a.k1 - s.k1) * r, std::abs(a.k2 - s.k2) * r});
    e1Error = std::max(e1Error, test::lineAngleDegrees(a.tangent, s.e1));
    EXPECT_GT(a.normal.dot(s.normal), 0.0);
  }
  EXPECT_LT(distanceError, 1e-5);   // float
  EXPECT_LT(normalError, 0.01);     // octahedral, 2 x 16 bits
  EXPECT_LT(curvatureError, 1e-3);  // half floats of k h
  EXPECT_LT(e1Error, 0.02);         // diamond angle, 16 bits

  // A level set: inside the tube negative, in the hole and far away positive.
  const auto valueAt = [&](const Eigen::Vector3d& world) {
    const openvdb::Vec3d index = grid.worldToIndex(openvdb::Vec3d(world.x(), world.y(), world.z()));
    return grid.tree().getValue(openvdb::Coord::round(index));
  };
  EXPECT_LT(valueAt(torus.center() + Eigen::Vector3d(R, 0, 0)), 0.0f);
  EXPECT_LT(valueAt(torus.center() + Eigen::Vector3d(0, -R, 0)), 0.0f);
  EXPECT_GT(valueAt(torus.center()), 0.0f);
  EXPECT_GT(valueAt(torus.center() + Eigen::Vector3d(0, 0, 0.8)), 0.0f);
}

TEST(FieldBand, NearSeedsWithTheSeedsReachFindsTheSameBand) {
  // Told that the seeds lie within 0.6 voxel of every torus point (0.5 by their spacing), the
  // band's candidates shrink (two 26-neighbour and two 6-neighbour steps instead of three and
  // one) and the band is the same: every voxel within 3 voxels of the torus.
  const double h = 0.03, R = 0.9, r = 0.3;
  const Torus torus(Eigen::Vector3d(0.02, -0.01, 0.005), R, r);
  const ApproximantField wide = exactTorusField(torus, R, r, h);
  const ApproximantField narrow = exactTorusField(torus, R, r, h, 0.6);
  std::set<std::tuple<int, int, int>> wideVoxels, narrowVoxels;
  for (auto voxel = wide.distanceGrid()->cbeginValueOn(); voxel; ++voxel) {
    wideVoxels.emplace(voxel.getCoord().x(), voxel.getCoord().y(), voxel.getCoord().z());
  }
  for (auto voxel = narrow.distanceGrid()->cbeginValueOn(); voxel; ++voxel) {
    narrowVoxels.emplace(voxel.getCoord().x(), voxel.getCoord().y(), voxel.getCoord().z());
  }
  EXPECT_GT(narrowVoxels.size(), 10000u);
  EXPECT_TRUE(wideVoxels == narrowVoxels);
  // And it is the band of the distance function itself.
  for (const auto& [i, j, k] : narrowVoxels) {
    ASSERT_LT(std::abs(torus.signedDistance(Eigen::Vector3d(i, j, k) * h)), 3.0 * h);
  }
}

TEST(FieldBand, SameFieldForOneAndTwoThreads) {
  const double h = 0.05, R = 0.8, r = 0.3;
  const Torus torus(Eigen::Vector3d::Zero(), R, r);
  const ApproximantField one = withThreads(1, [&] { return exactTorusField(torus, R, r, h); });
  const ApproximantField two = withThreads(2, [&] { return exactTorusField(torus, R, r, h); });
  test::expectBitwiseIdentical(*one.distanceGrid(), *two.distanceGrid());
  expectSameAnswers(one, two, randomPoints(one.domain(), 3000));
}

// A band over an existing level set's voxels whose approximants are not the grid's values: the
// field's distance grid is a copy holding the approximants' distances, the input is untouched.
TEST(FieldBand, ActiveVoxelsOfAGridTakeTheApproximantsDistances) {
  const double h = 0.04;
  const Sphere sphere(Eigen::Vector3d(0.01, 0.0, -0.02), 0.7);
  const Sphere larger(sphere.center(), 0.7 + 0.25 * h);
  const auto levelSet = primitiveLevelSet(sphere, {h, 3.0});
  const auto original = levelSet->deepCopy();
  FieldBand band = FieldBand::activeVoxelsOf(TargetKind::Surface, levelSet);
  band.setApproximants([&](const openvdb::Coord&, const Eigen::Vector3d& center) {
    return exactApproximant(larger, center);
  });
  const ApproximantField field = ApproximantField::fromBand(band);
  test::expectBitwiseIdentical(*levelSet, *original);
  ASSERT_NE(field.distanceGrid(), openvdb::FloatGrid::ConstPtr(levelSet));
  ASSERT_TRUE(field.distanceGrid()->tree().hasSameTopology(levelSet->tree()));
  EXPECT_EQ(field.distanceGrid()->getName(), levelSet->getName());
  for (auto voxel = field.distanceGrid()->cbeginValueOn(); voxel; ++voxel) {
    const openvdb::Vec3d w = field.distanceGrid()->indexToWorld(voxel.getCoord());
    ASSERT_EQ(*voxel,
              static_cast<float>(larger.signedDistance(Eigen::Vector3d(w.x(), w.y(), w.z()))));
  }
  // The default target bounds: the band's voxel centres, padded by half their size.
  const openvdb::CoordBBox box = levelSet->evalActiveVoxelBoundingBox();
  EXPECT_NEAR(field.domain().sizes().x(), 2.0 * (box.dim().x() - 1) * h, 1e-9);
  // Where the grid already holds the approximants' distances, it is shared, not copied.
  FieldBand same = FieldBand::activeVoxelsOf(TargetKind::Surface, levelSet);
  same.setApproximants([&](const openvdb::Coord&, const Eigen::Vector3d& center) {
    Approximant a = exactApproximant(sphere, center);
    a.distance = static_cast<float>(a.distance);
    return a;
  });
  EXPECT_EQ(ApproximantField::fromBand(same).distanceGrid(),
            openvdb::FloatGrid::ConstPtr(levelSet));
}

TEST(FieldBand, RefusesBadBandsWithClearErrors) {
  const double h = 0.05;
  const Sphere sphere(Eigen::Vector3d::Zero(), 0.5);
  const std::vector<Eigen::Vector3d> seeds = {Eigen::Vector3d(0.5, 0, 0),
                                              Eigen::Vector3d(-0.5, 0, 0)};
  const auto expectError = [](const FieldBand& band, const std::string& fragment,
                              const ApproximantFieldOptions& options = {}) {
    try {
      ApproximantField::fromBand(band, options);
      ADD_FAILURE() << "accepted a band that should fail with '" << fragment << "'";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
    }
  };
  const auto exact = [&](const openvdb::Coord&, const Eigen::Vector3d& center) {
    return exactApproximant(sphere, center);
  };
  expectError(FieldBand::nearSeeds(TargetKind::Surface, seeds, h, 3.0).setLabel("no function"),
              "no function: the band has no approximant function");
  expectError(FieldBand::nearSeeds(TargetKind::Surface, {}, h, 3.0).setApproximants(exact),
              "no seed points");
  expectError(
      FieldBand::nearSeeds(TargetKind::Surface, {Eigen::Vector3d(0, std::nan(""), 0)}, h, 3.0)
          .setApproximants(exact),
      "seed point 0 is not finite");
  expectError(FieldBand::nearSeeds(TargetKind::Surface, seeds, -h, 3.0).setApproximants(exact),
              "voxel size");
  expectError(FieldBand::nearSeeds(TargetKind::Surface, seeds, h, 0.5).setApproximants(exact),
              "half-width");
  expectError(FieldBand::nearSeeds(TargetKind::Surface, seeds, h, 3.0, 0.0).setApproximants(exact),
              "reach");
  expectError(
      FieldBand::nearSeeds(TargetKind::Surface, seeds, h, 3.0, std::nan("")).setApproximants(exact),
      "reach");
  // Approximants with NaN or a normal that is not a unit vector.
  expectError(FieldBand::nearSeeds(TargetKind::Surface, seeds, h, 3.0)
                  .setApproximants([&](const openvdb::Coord& ijk, const Eigen::Vector3d& c) {
                    Approximant a = exact(ijk, c);
                    a.k1 = std::nan("");
                    return a;
                  }),
              "non-finite values");
  expectError(FieldBand::activeVoxelsOf(TargetKind::Surface, primitiveLevelSet(sphere, {h, 3.0}))
                  .setApproximants([&](const openvdb::Coord& ijk, const Eigen::Vector3d& c) {
                    Approximant a = exact(ijk, c);
                    a.normal *= 2.0;
                    return a;
                  }),
              "not a unit vector");
  // Too many voxels for the budget; a target the voxels do not resolve.
  ApproximantFieldOptions small;
  small.maxActiveVoxels = 100;
  expectError(FieldBand::nearSeeds(TargetKind::Surface, seeds, h, 3.0).setApproximants(exact),
              "above the limit of 100;", small);
  // (distances 0.9 voxel too long: only the point's own voxel is kept, and it is no sample)
  expectError(FieldBand::nearSeeds(TargetKind::Points, {Eigen::Vector3d::Zero()}, h, 1.0)
                  .setApproximants([h](const openvdb::Coord&, const Eigen::Vector3d& c) {
                    Approximant a;
                    a.kind = TargetKind::Points;
                    a.distance = c.norm() + 0.9 * h;
                    a.normal = Eigen::Vector3d::UnitX();
                    return a;
                  }),
              "not resolved");
  // What the function throws reaches the caller.
  EXPECT_THROW(
      ApproximantField::fromBand(
          FieldBand::nearSeeds(TargetKind::Surface, seeds, h, 3.0)
              .setApproximants([](const openvdb::Coord&, const Eigen::Vector3d&) -> Approximant {
                throw std::domain_error("projection failed");
              })),
      std::domain_error);
}

}  // namespace
}  // namespace d2vdb
