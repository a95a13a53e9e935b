#include "d2vdb/support/PiecewiseLinearSupport.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

#include "SupportTestSupport.h"
#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

// Hausdorff distance between the dual polyhedron of the ellipsoid's support function (sampled at
// the vertices of `sphere`) and the ellipsoid. The polyhedron circumscribes the ellipsoid (its
// faces are tangent planes), so the largest distance from the polyhedron is at one of its
// vertices, and the distance of an ellipsoid point from the polyhedron's boundary is its distance
// to the nearest face plane.
double hausdorff(const PiecewiseLinearSupport& pl, const test::Ellipsoid& ellipsoid) {
  double worst = 0.0;
  for (const Eigen::Vector3d& v : pl.dualVertices()) {
    worst = std::max(worst, test::signedDistanceToEllipsoid(ellipsoid, v));
  }
  const auto& normals = pl.triangulation().normals;
  for (const Eigen::Vector3d& n : test::randomUnitVectors(3000, 77)) {
    const Eigen::Vector3d p = ellipsoid.point(n);
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < normals.size(); ++i) {
      nearest = std::min(nearest, pl.values()[i] - normals[i].dot(p));
    }
    worst = std::max(worst, nearest);
  }
  return worst;
}

TEST(PiecewiseLinearSupport, OffsetsOfTheDualPolyhedronAreExact) {
  const test::Ellipsoid ellipsoid;
  PiecewiseLinearSupport pl = PiecewiseLinearSupport::sample(
      [&](const Eigen::Vector3d& n) { return ellipsoid.support(n); }, geodesicSphere(3));
  pl.removeSwallowtails();
  for (const double d : {-0.3, 0.25, 1.0}) {
    const PiecewiseLinearSupport moved = pl.offset(d);
    const auto before = pl.dualVertices();
    const auto after = moved.dualVertices();
    const auto& tris = pl.triangulation().triangles;
    const auto& normals = pl.triangulation().normals;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      for (const auto i : tris[t]) {
        // Every face of the offset lies in its plane moved by exactly d.
        EXPECT_NEAR(normals[i].dot(after[t]), pl.values()[i] + d, 1e-12);
        EXPECT_NEAR(normals[i].dot(after[t] - before[t]), d, 1e-12);
      }
    }
  }
}

TEST(PiecewiseLinearSupport, EdgeFlipsRemoveSwallowtailsAndGiveTheConvexPolyhedron) {
  const test::Ellipsoid ellipsoid{3.0, 1.0, 0.4, Eigen::Vector3d(0.1, -0.2, 0.05)};
  PiecewiseLinearSupport pl = PiecewiseLinearSupport::sample(
      [&](const Eigen::Vector3d& n) { return ellipsoid.support(n); }, geodesicSphere(2));
  const std::size_t foldedBefore = pl.foldedEdges();
  EXPECT_GT(foldedBefore, 0u);  // this elongated ellipsoid folds the icosphere's dual
  const std::size_t flips = pl.removeSwallowtails();
  EXPECT_GT(flips, 0u);
  EXPECT_EQ(pl.foldedEdges(), 0u);
  // Globally convex: every dual vertex satisfies every plane.
  const auto vertices = pl.dualVertices();
  const auto& normals = pl.triangulation().normals;
  double violation = 0.0;
  for (const Eigen::Vector3d& v : vertices) {
    for (std::size_t i = 0; i < normals.size(); ++i) {
      violation = std::max(violation, normals[i].dot(v) - pl.values()[i]);
    }
  }
  EXPECT_LT(violation, 1e-12);
  // The dual polyhedron is a closed, consistently oriented mesh enclosing the ellipsoid.
  const test::ClosedMeshCheck check = test::checkClosedMesh(pl.dualPolyhedron());
  EXPECT_TRUE(check.closedAndOriented);
  EXPECT_GT(check.volume, 4.0 / 3.0 * kPi * 3.0 * 1.0 * 0.4);
}

// The dual polyhedron of an icosphere-sampled ellipsoid converges like h^2 in the Hausdorff
// distance (h halves per subdivision, so the distance should fall by about 4 per level).
TEST(PiecewiseLinearSupport, DualPolyhedronConvergesQuadratically) {
  const test::Ellipsoid ellipsoid;
  std::vector<double> distances;
  for (int level = 1; level <= 4; ++level) {
    PiecewiseLinearSupport pl = PiecewiseLinearSupport::sample(
        [&](const Eigen::Vector3d& n) { return ellipsoid.support(n); }, geodesicSphere(level));
    pl.removeSwallowtails();
    EXPECT_EQ(pl.foldedEdges(), 0u);
    distances.push_back(hausdorff(pl, ellipsoid));
  }
  std::printf(
      "dual polyhedron Hausdorff distance by subdivision 1..4: %.4g %.4g %.4g %.4g; "
      "rates %.3f %.3f %.3f\n",
      distances[0], distances[1], distances[2], distances[3],
      std::log2(distances[0] / distances[1]), std::log2(distances[1] / distances[2]),
      std::log2(distances[2] / distances[3]));
  EXPECT_GT(std::log2(distances[2] / distances[3]), 1.8);
  EXPECT_GT(std::log2(distances[1] / distances[2]), 1.8);
}

TEST(PiecewiseLinearSupport, RejectsBadInput) {
  SphericalTriangulation sphere = geodesicSphere(0);
  EXPECT_THROW(PiecewiseLinearSupport(sphere, std::vector<double>(5, 1.0)), InputError);
  std::vector<double> values(sphere.normals.size(), 1.0);
  values[3] = std::nan("");
  EXPECT_THROW(PiecewiseLinearSupport(sphere, values), InputError);
  SphericalTriangulation broken = sphere;
  broken.triangles[0][1] = 999;
  EXPECT_THROW(PiecewiseLinearSupport(broken, std::vector<double>(sphere.normals.size(), 1.0)),
               InputError);
  const PiecewiseLinearSupport unit(sphere, std::vector<double>(sphere.normals.size(), 1.0));
  EXPECT_THROW(unit.offset(std::nan("")), InputError);
}

}  // namespace
}  // namespace d2vdb
