// The pieces of exact mesh signs: closest points with their feature, the hierarchical winding
// number and its error bound against brute force, the self-intersection test, and the prepared
// mesh (welding, orientation repair, caps, pseudonormals).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "common/AppendMesh.h"
#include "d2vdb/field/detail/InsideOutsideMesh.h"
#include "d2vdb/field/detail/RayWinding.h"
#include "d2vdb/field/detail/SelfIntersection.h"
#include "d2vdb/field/detail/WindingNumber.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/TriangleClosestPoint.h"
#include "field/FieldTestSupport.h"
#include "field/PolycubeMeshes.h"
#include "field/WindingNumberReference.h"

namespace d2vdb {
namespace {

bool anyMarked(const std::vector<bool>& marks) {
  return std::find(marks.begin(), marks.end(), true) != marks.end();
}

std::vector<Eigen::Vector3d> toDouble(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3f& p : mesh.positions) points.push_back(p.cast<double>());
  return points;
}

std::vector<TriangleIndices> toIndices(const TriangleMesh& mesh) {
  std::vector<TriangleIndices> triangles;
  for (const TriangleMesh::Triangle& t : mesh.triangles) triangles.push_back({t[0], t[1], t[2]});
  return triangles;
}

TEST(InsideOutside, ClosestPointReportsItsFeature) {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  const auto at = [&](double x, double y, double z) {
    return closestPointOnTriangle(Eigen::Vector3d(x, y, z), a, b, c);
  };
  EXPECT_EQ(at(0.5, 0.5, 1).feature, TriangleFeature::face);
  EXPECT_TRUE(at(0.5, 0.5, 1).point.isApprox(Eigen::Vector3d(0.5, 0.5, 0)));
  EXPECT_EQ(at(1, -1, 0.3).feature, TriangleFeature::edge0);   // below ab
  EXPECT_EQ(at(1.5, 1.5, 0).feature, TriangleFeature::edge1);  // beyond bc
  EXPECT_TRUE(at(1.5, 1.5, 0).point.isApprox(Eigen::Vector3d(1, 1, 0)));
  EXPECT_EQ(at(-1, 1, 0).feature, TriangleFeature::edge2);
  EXPECT_EQ(at(-1, -1, 5).feature, TriangleFeature::vertex0);
  EXPECT_EQ(at(3, -1, 0).feature, TriangleFeature::vertex1);
  EXPECT_EQ(at(-0.5, 3, 0).feature, TriangleFeature::vertex2);
  // A flat triangle: the nearest of its sides.
  const TriangleClosestPoint flat = closestPointOnTriangle(
      Eigen::Vector3d(1, 1, 0), a, Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(4, 0, 0));
  EXPECT_NEAR((flat.point - Eigen::Vector3d(1, 0, 0)).norm(), 0.0, 1e-12);
}

TEST(InsideOutside, HierarchicalWindingNumberStaysWithinItsBound) {
  // The bunny, at 256 voxels across, queried near and far from its surface.
  const TriangleMesh bunny =
      readMesh(std::filesystem::path(D2VDB_SOURCE_DIR) / "volumes" / "bunny.obj");
  std::vector<Eigen::Vector3d> points = toDouble(bunny);
  for (Eigen::Vector3d& p : points) p *= 16.0;
  const std::vector<TriangleIndices> triangles = toIndices(bunny);
  const detail::WindingNumberField field(points, triangles);
  std::mt19937 random(5);
  double largestError = 0.0;
  int insideCount = 0;
  for (int n = 0; n < 400; ++n) {
    const Eigen::Vector3d& vertex = points[random() % points.size()];
    const double reach = n < 300 ? 3.0 : 60.0;
    const Eigen::Vector3d q = vertex + Eigen::Vector3d(test::uniform(random, -reach, reach),
                                                       test::uniform(random, -reach, reach),
                                                       test::uniform(random, -reach, reach));
    const double exact = field.exact(q);
    // A closed mesh: an integer away from the surface.
    ASSERT_NEAR(exact, std::round(exact), 1e-6);
    insideCount += std::lround(exact) == 1;
    for (const double beta : {2.0, 3.0, 6.0}) {
      const detail::WindingNumberField::Estimate e = field.estimate(q, beta);
      EXPECT_LE(std::abs(e.value - exact), e.errorBound) << "beta " << beta;
      if (beta == 2.0) largestError = std::max(largestError, std::abs(e.value - exact));
    }
    EXPECT_EQ(field.integerValue(q), std::lround(exact));
    EXPECT_EQ(field.atLeastHalf(q), exact >= 0.5);
  }
  EXPECT_GT(insideCount, 50);
  // Barill et al.'s accuracy at beta = 2 (second order): small against the 1/2 that matters.
  EXPECT_LT(largestError, 0.01);
  // Excluding a face: W of the rest at its centroid is W in front + 1/2.
  const TriangleIndices& face = triangles[100];
  const Eigen::Vector3d centroid = (points[face[0]] + points[face[1]] + points[face[2]]) / 3.0;
  EXPECT_NEAR(field.exact(centroid, 100), 0.5, 1e-9);
}

TEST(InsideOutside, OrientationSignIsCertainOrInDoubt) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(detail::certifiedOrientation(a, b, c, Eigen::Vector3d(0.2, 0.2, -1.0)), 1);  // behind
  EXPECT_EQ(detail::certifiedOrientation(a, b, c, Eigen::Vector3d(0.2, 0.2, 1e-3)), -1);
  EXPECT_EQ(detail::certifiedOrientation(a, b, c, Eigen::Vector3d(5.0, -3.0, 0.0)), 0);  // plane
  // Off the plane by far less than rounding of coordinates near 1e6: in doubt, not a guess.
  const Eigen::Vector3d far(1e6, 1e6, 1e6);
  EXPECT_EQ(detail::certifiedOrientation(far + a, far + b, far + c,
                                         far + Eigen::Vector3d(0.3, 0.3, 1e-12)),
            0);
}

TEST(InsideOutside, RayCrossingsGiveTheWindingNumberOfWatertightMeshes) {
  // Two overlapping spheres (W = 2 in the overlap) and a capped sphere with holes, against the
  // brute-force winding number; queries include vertices' neighbourhoods, where rays through
  // edges must be discarded.
  TriangleMesh spheres = test::makeIcosphere(Eigen::Vector3d(0.0, 0.0, 0.0), 1.0, 2);
  test::append(spheres, test::makeIcosphere(Eigen::Vector3d(0.7, 0.2, 0.1), 0.8, 2));
  TriangleMesh holed = test::makeIcosphere(Eigen::Vector3d(0.1, 0.2, 0.3), 1.0, 2);
  holed.triangles.erase(holed.triangles.begin() + 200);
  holed.triangles.erase(holed.triangles.begin() + 100);
  std::mt19937 random(9);
  int twos = 0, ones = 0, rejected = 0;
  for (const TriangleMesh* input : {&spheres, &holed}) {
    const detail::InsideOutsideMesh mesh =
        detail::prepareInsideOutsideMesh(toDouble(*input), toIndices(*input));
    const detail::WindingNumberField field(mesh.points, mesh.triangles);
    for (int n = 0; n < 600; ++n) {
      Eigen::Vector3d q(test::uniform(random, -1.5, 2.0), test::uniform(random, -1.5, 1.5),
                        test::uniform(random, -1.5, 1.5));
      if (n % 3 == 0) q = mesh.points[random() % mesh.points.size()];  // on a vertex
      const std::optional<long> w =
          detail::rayWindingNumber(field.hierarchy(), mesh.points, mesh.triangles, q);
      const double exact = field.exact(q);
      if (n % 3 == 0) {
        // On the surface no ray can be certain.
        EXPECT_FALSE(w.has_value()) << q.transpose();
        rejected += !w.has_value();
        continue;
      }
      ASSERT_TRUE(w.has_value()) << q.transpose();
      ASSERT_NEAR(exact, std::round(exact), 1e-6);
      EXPECT_EQ(*w, std::lround(exact)) << q.transpose();
      twos += *w == 2;
      ones += *w == 1;
    }
  }
  EXPECT_GT(twos, 5);
  EXPECT_GT(ones, 50);
  EXPECT_EQ(rejected, 400);
}

TEST(InsideOutside, SelfIntersectionTestCases) {
  std::vector<Eigen::Vector3d> p = {
      {0, 0, 0},      {2, 0, 0},     {0, 2, 0},   // 0-2: in z = 0
      {0.5, 0.5, -1}, {0.5, 0.5, 1}, {3, 3, 0},   // 3-5: pierces the first
      {5, 5, 5},      {6, 5, 5},     {5, 6, 5},   // 6-8: far away
      {1, 1, 0},      {3, 1, 1},     {3, 1, -1},  // 9-11: touches the first at a point of its edge
      {0.5, 0.2, 0},  {1.5, 0.2, 0}, {0.5, 1.2, 0},  // 12-14: coplanar, overlapping
      {-1, 0, 0},     {-2, 0, 0},    {-1.5, -1, 0},  // 15-17: coplanar, disjoint, edges collinear
      {1, 1, 0.5},    {2, -1, 0}};                   // 18, 19
  const double tolerance = 1e-9;
  const auto meet = [&](TriangleIndices a, TriangleIndices b) {
    return detail::trianglesIntersect(p, a, b, tolerance);
  };
  EXPECT_TRUE(meet({0, 1, 2}, {3, 4, 5}));
  EXPECT_FALSE(meet({0, 1, 2}, {6, 7, 8}));
  EXPECT_TRUE(meet({0, 1, 2}, {9, 10, 11}));
  EXPECT_TRUE(meet({0, 1, 2}, {12, 13, 14}));
  EXPECT_FALSE(meet({0, 1, 2}, {15, 16, 17}));
  // Sharing an edge: only a flat fold meets elsewhere.
  EXPECT_FALSE(meet({0, 1, 2}, {1, 0, 19}));  // the neighbour across edge 01, flat, other side
  EXPECT_TRUE(meet({0, 1, 2}, {1, 0, 12}));   // folded onto the first
  EXPECT_FALSE(meet({0, 1, 2}, {1, 0, 18}));  // a proper dihedral angle
  // Sharing a corner: only when one runs into the other.
  EXPECT_FALSE(meet({0, 1, 2}, {0, 15, 17}));  // coplanar, the next sector
  EXPECT_TRUE(meet({0, 1, 2}, {0, 13, 14}));   // coplanar, inside its angle
  EXPECT_TRUE(meet({0, 1, 2}, {0, 3, 18}));    // crosses it
  EXPECT_TRUE(meet({0, 1, 2}, {0, 1, 2}));     // the same triangle twice
  // A long chain of collinear coplanar edges (as midpoint subdivision makes) is not an
  // intersection: the regression that once sent the subdivided bunny down the slow path.
  std::vector<Eigen::Vector3d> chain;
  for (int i = 0; i < 4; ++i) {
    chain.push_back(Eigen::Vector3d(1000.0 + 7.3 * i, 300.0 + 2.1 * i, -11.0 - 4.4 * i));
    chain.push_back(chain.back() + Eigen::Vector3d(0.9, -4.0, 2.0));
  }
  EXPECT_FALSE(detail::trianglesIntersect(chain, {0, 2, 1}, {4, 6, 5}, 1e-7));
  // Whole meshes: a jittered polycube does not intersect itself; two overlapping copies do.
  test::PolycubeSpec spec;
  spec.genus = 2;
  spec.seed = 9;
  const TriangleMesh polycube = test::makePolycubeMesh(spec);
  const detail::InsideOutsideMesh single =
      detail::prepareInsideOutsideMesh(toDouble(polycube), toIndices(polycube));
  const TriangleBvh bvh(single.points, single.triangles);
  EXPECT_FALSE(anyMarked(detail::selfIntersectingTriangles(single.points, single.triangles,
                                                           single.degenerate, bvh, 1e-9)));
  TriangleMesh doubled = polycube;
  const auto offset = static_cast<TriangleMesh::Index>(doubled.positions.size());
  for (const Eigen::Vector3f& q : polycube.positions) {
    doubled.positions.push_back(q + Eigen::Vector3f(0.3f, 0.2f, 0.1f));
  }
  for (TriangleMesh::Triangle t : polycube.triangles) {
    for (TriangleMesh::Index& v : t) v += offset;
    doubled.triangles.push_back(t);
  }
  const detail::InsideOutsideMesh pair =
      detail::prepareInsideOutsideMesh(toDouble(doubled), toIndices(doubled));
  const TriangleBvh pairBvh(pair.points, pair.triangles);
  EXPECT_TRUE(anyMarked(detail::selfIntersectingTriangles(pair.points, pair.triangles,
                                                          pair.degenerate, pairBvh, 1e-9)));
}

TEST(InsideOutside, SelfIntersectionBroadPhaseFindsWhatAllPairsFind) {
  // Random soups of small triangles, some sharing corners: the hierarchical search must mark
  // exactly the triangles the test of every pair marks.
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int intersecting = 0;
  for (int soup = 0; soup < 150; ++soup) {
    const double size = 0.05 + 0.25 * unit(random);
    std::vector<Eigen::Vector3d> points;
    std::vector<TriangleIndices> triangles;
    for (int t = 0; t < 24; ++t) {
      const Eigen::Vector3d center(unit(random), unit(random), unit(random));
      const auto corner = [&] {
        points.push_back(center + size * Eigen::Vector3d(unit(random) - 0.5, unit(random) - 0.5,
                                                         unit(random) - 0.5));
        return static_cast<std::uint32_t>(points.size() - 1);
      };
      // Every fourth triangle reuses a corner of the previous one.
      const std::uint32_t first = (t % 4 == 3) ? triangles.back()[0] : corner();
      triangles.push_back({first, corner(), corner()});
    }
    std::vector<bool> degenerate(triangles.size(), false);
    std::vector<bool> bruteForceMarks(triangles.size(), false);
    for (std::size_t a = 0; a < triangles.size(); ++a) {
      for (std::size_t b = a + 1; b < triangles.size(); ++b) {
        if (detail::trianglesIntersect(points, triangles[a], triangles[b], 1e-9)) {
          bruteForceMarks[a] = bruteForceMarks[b] = true;
        }
      }
    }
    const bool bruteForce = anyMarked(bruteForceMarks);
    const TriangleBvh bvh(points, triangles, 2);
    EXPECT_EQ(detail::selfIntersectingTriangles(points, triangles, degenerate, bvh, 1e-9),
              bruteForceMarks)
        << "soup " << soup;
    intersecting += bruteForce ? 1 : 0;
  }
  // Both answers occur often enough for the comparison to mean something.
  EXPECT_GT(intersecting, 20);
  EXPECT_LT(intersecting, 130);
}

TEST(InsideOutside, RepairedClosedMeshHasTheAdjacencyOfAWellWoundOne) {
  // Flipped triangles of a closed mesh are reversed back; the mates found through the repaired
  // half-edges equal those of the mesh that was never flipped, and every mate is mutual and
  // joins the same two corners the other way.
  const TriangleMesh sphere = test::makeIcosphere(Eigen::Vector3d(0.1, 0.2, 0.3), 1.0, 2);
  TriangleMesh flipped = sphere;
  for (const std::size_t t : {3u, 50u, 51u, 52u, 200u}) {
    std::swap(flipped.triangles[t][1], flipped.triangles[t][2]);
  }
  const detail::InsideOutsideMesh reference =
      detail::prepareInsideOutsideMesh(toDouble(sphere), toIndices(sphere));
  const detail::InsideOutsideMesh repaired =
      detail::prepareInsideOutsideMesh(toDouble(flipped), toIndices(flipped));
  EXPECT_EQ(reference.reorientedTriangles, 0u);
  EXPECT_EQ(repaired.reorientedTriangles, 5u);
  EXPECT_TRUE(repaired.watertight);
  EXPECT_EQ(repaired.triangles, reference.triangles);
  EXPECT_EQ(repaired.mate, reference.mate);
  for (std::uint32_t h = 0; h < repaired.mate.size(); ++h) {
    const std::uint32_t other = repaired.mate[h];
    ASSERT_NE(other, detail::InsideOutsideMesh::kNoMate) << "half-edge " << h;
    EXPECT_EQ(repaired.mate[other], h);
    const TriangleIndices& a = repaired.triangles[h / 3];
    const TriangleIndices& b = repaired.triangles[other / 3];
    EXPECT_EQ(a[h % 3], b[(other % 3 + 1) % 3]);
    EXPECT_EQ(a[(h % 3 + 1) % 3], b[other % 3]);
  }
}

TEST(InsideOutside, PreparedMeshIsRepairedAndCapped) {
  TriangleMesh sphere = test::makeIcosphere(Eigen::Vector3d(0.1, 0.2, 0.3), 1.0, 2);
  // Unweld one vertex (a seam), flip two triangles, cut two holes.
  const TriangleMesh::Index seam = sphere.triangles[10][0];
  sphere.positions.push_back(sphere.positions[seam]);
  sphere.triangles[10][0] = static_cast<TriangleMesh::Index>(sphere.positions.size() - 1);
  std::swap(sphere.triangles[50][1], sphere.triangles[50][2]);
  std::swap(sphere.triangles[51][1], sphere.triangles[51][2]);
  sphere.triangles.erase(sphere.triangles.begin() + 200);
  sphere.triangles.erase(sphere.triangles.begin() + 100);
  const detail::InsideOutsideMesh mesh =
      detail::prepareInsideOutsideMesh(toDouble(sphere), toIndices(sphere));
  EXPECT_EQ(mesh.reorientedTriangles, 2u);
  EXPECT_FALSE(mesh.watertight);
  EXPECT_EQ(mesh.capLoops, 2u);
  EXPECT_EQ(mesh.boundaryEdges, 6u);
  EXPECT_EQ(mesh.caps.size(), 6u);
  EXPECT_EQ(mesh.meshTriangleCount, sphere.triangles.size());
  EXPECT_EQ(mesh.componentCount, 1u);  // M + S is one closed surface
  // Every edge of M + S has a mate running the other way.
  for (std::size_t h = 0; h < mesh.mate.size(); ++h) {
    ASSERT_NE(mesh.mate[h], detail::InsideOutsideMesh::kNoMate) << h;
    EXPECT_EQ(mesh.mate[mesh.mate[h]], h);
  }
  // W of M + S is 1 at the centre, 0 far away; the caps' own is small at the centre.
  const detail::WindingNumberField closed(mesh.points, mesh.triangles);
  EXPECT_EQ(closed.integerValue(Eigen::Vector3d(0.1, 0.2, 0.3)), 1);
  EXPECT_EQ(closed.integerValue(Eigen::Vector3d(5, 5, 5)), 0);
  // The pseudonormal side test: outside points in front, inside points behind.
  for (const Eigen::Vector3d& q : {Eigen::Vector3d(1.3, 0.2, 0.3), Eigen::Vector3d(0.1, 0.2, -0.5),
                                   Eigen::Vector3d(0.8, 0.8, 0.9)}) {
    const bool inside = (q - Eigen::Vector3d(0.1, 0.2, 0.3)).norm() < 0.9;
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t nearest = 0;
    TriangleClosestPoint closest;
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      const TriangleIndices& tri = mesh.triangles[t];
      const TriangleClosestPoint c =
          closestPointOnTriangle(q, mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]);
      if ((c.point - q).norm() < best) {
        best = (c.point - q).norm();
        nearest = t;
        closest = c;
      }
    }
    EXPECT_EQ(mesh.side(nearest, closest, q),
              inside ? detail::SurfaceSide::back : detail::SurfaceSide::front);
  }
}

}  // namespace
}  // namespace d2vdb
