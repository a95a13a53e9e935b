// MeshDistance: closest points on the unit cube's twelve triangles against the cube's analytic
// distance, a sliver and a degenerate triangle, and the refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "MeshTestSupport.h"
#include "common/ExpectInputError.h"
#include "d2vdb/mesh/MeshDistance.h"

namespace d2vdb {
namespace {

/// Distance from p to the surface of the box [0, 1]^3: outside, the length of the excess over
/// the box; inside, the smallest gap to a face.
double distanceToUnitCubeSurface(const Eigen::Vector3d& p) {
  const Eigen::Vector3d excess =
      (p - Eigen::Vector3d::Ones()).cwiseMax(-p).cwiseMax(Eigen::Vector3d::Zero());
  if (excess.squaredNorm() > 0.0) return excess.norm();
  return std::min(p.minCoeff(), (Eigen::Vector3d::Ones() - p).minCoeff());
}

TEST(MeshDistance, MatchesTheUnitCubesAnalyticDistanceInsideAndOutside) {
  const MeshDistance cube(test::cube());
  EXPECT_EQ(cube.triangleCount(), 12u);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 2.0);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p(coordinate(random), coordinate(random), coordinate(random));
    const MeshClosestPoint closest = cube.closestPoint(p);
    ASSERT_NEAR(closest.distance, distanceToUnitCubeSurface(p), 1e-12) << p.transpose();
    EXPECT_NEAR((closest.point - p).norm(), closest.distance, 1e-12);
    // The closest point lies on the cube's surface: inside the box, on one of its faces.
    EXPECT_LE(closest.point.maxCoeff(), 1.0 + 1e-12);
    EXPECT_GE(closest.point.minCoeff(), -1e-12);
    EXPECT_LT(std::min(closest.point.minCoeff(), 1.0 - closest.point.maxCoeff()), 1e-12);
    EXPECT_LT(closest.triangle, 12u);
  }
}

TEST(MeshDistance, AnswersAtCornersEdgesAndOnTheSurface) {
  const MeshDistance cube(test::cube());
  // Beyond a corner, beyond an edge, above a face, on a face.
  EXPECT_NEAR(cube.closestPoint({2.0, 2.0, 2.0}).distance, std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(cube.closestPoint({2.0, -1.0, 0.5}).distance, std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(cube.closestPoint({0.25, 0.5, 3.0}).distance, 2.0, 1e-15);
  EXPECT_EQ(cube.closestPoint({0.25, 0.5, 1.0}).distance, 0.0);
}

TEST(MeshDistance, DegenerateTrianglesHaveClosestPointsOnTheirSegment) {
  // Three collinear corners: the triangle is the segment from (0,0,0) to (2,0,0).
  const MeshDistance segment(test::makeMesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 1, 2}}));
  EXPECT_NEAR(segment.closestPoint({1.5, 3.0, 4.0}).distance, 5.0, 1e-15);
  EXPECT_NEAR(segment.closestPoint({-3.0, 0.0, 4.0}).distance, 5.0, 1e-15);
}

TEST(MeshDistance, RefusesEmptyAndBrokenMeshesAndNonFiniteQueries) {
  test::expectInputError([] { MeshDistance{TriangleMesh{}}; }, {"no triangles"});
  test::expectInputError(
      [] {
        MeshDistance{test::makeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 3}})};
      },
      {"names vertex 3 of 3"});
  const float nan = std::numeric_limits<float>::quiet_NaN();
  test::expectInputError(
      [nan] {
        MeshDistance{test::makeMesh({{0, 0, 0}, {nan, 0, 0}, {0, 1, 0}}, {{0, 1, 2}})};
      },
      {"vertex 1 has a non-finite coordinate"});
  const MeshDistance cube(test::cube());
  test::expectInputError(
      [&] {
        cube.closestPoint({0.0, std::numeric_limits<double>::infinity(), 0.0});
      },
      {"non-finite"});
}

}  // namespace
}  // namespace d2vdb
