// The certified Hausdorff bracket between triangle shapes, against exact cases worked by hand
// (boxes, translated copies, nested spheres) and brute force (dense sampling with an independent
// point-triangle distance).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "common/ExpectInputError.h"
#include "common/Icosphere.h"
#include "common/WithThreads.h"
#include "d2vdb/measure/MeshHausdorff.h"
#include "d2vdb/measure/detail/CertifiedDistance.h"

namespace d2vdb {
namespace {

using Points = std::vector<Eigen::Vector3d>;

/// The closed box [low, high] as 12 triangles (outward winding does not matter here).
HausdorffShape boxShape(const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  HausdorffShape box;
  for (int corner = 0; corner < 8; ++corner) {
    box.points.emplace_back(corner & 1 ? high.x() : low.x(), corner & 2 ? high.y() : low.y(),
                            corner & 4 ? high.z() : low.z());
  }
  box.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return box;
}

HausdorffShape sphereShape(double radius, int levels) {
  const test::UnitIcosphere sphere = test::unitIcosphere(levels);
  HausdorffShape shape;
  for (const Eigen::Vector3d& point : sphere.positions) shape.points.push_back(radius * point);
  shape.triangles = sphere.triangles;
  return shape;
}

/// The distance from p to the triangle by an independent method in long double: the projection
/// onto the plane when it falls inside, else the nearest of the three sides.
long double referenceDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  using Vector = Eigen::Matrix<long double, 3, 1>;
  const Vector P = p.cast<long double>(), A = a.cast<long double>(), B = b.cast<long double>(),
               C = c.cast<long double>();
  const auto segment = [&](const Vector& from, const Vector& to) {
    const Vector along = to - from;
    const long double length2 = along.squaredNorm();
    long double t = length2 > 0 ? (P - from).dot(along) / length2 : 0;
    t = std::clamp<long double>(t, 0, 1);
    return (P - (from + t * along)).norm();
  };
  long double best = std::min({segment(A, B), segment(B, C), segment(C, A)});
  const Vector normal = (B - A).cross(C - A);
  const long double area2 = normal.squaredNorm();
  if (area2 > 0) {
    const Vector projected = P - normal * ((P - A).dot(normal) / area2);
    const auto side = [&](const Vector& u, const Vector& v) {
      return (v - u).cross(projected - u).dot(normal) >= 0;
    };
    if (side(A, B) && side(B, C) && side(C, A)) best = std::min(best, (P - projected).norm());
  }
  return best;
}

/// max over dense samples of `from` of the exact distance to `to` (brute force): a lower bound of
/// h(from -> to) that is within `spacing` of it.
double sampledDirected(const HausdorffShape& from, const HausdorffShape& to, int samples,
                       double* spacing) {
  double largest = 0.0, step = 0.0;
  for (const TriangleIndices& t : from.triangles) {
    const Eigen::Vector3d &a = from.points[t[0]], &b = from.points[t[1]], &c = from.points[t[2]];
    step = std::max(step, std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()}) / samples);
    for (int i = 0; i <= samples; ++i) {
      for (int j = 0; i + j <= samples; ++j) {
        const Eigen::Vector3d x =
            a + (double(i) / samples) * (b - a) + (double(j) / samples) * (c - a);
        long double nearest = INFINITY;
        for (const TriangleIndices& s : to.triangles) {
          nearest = std::min(
              nearest, referenceDistance(x, to.points[s[0]], to.points[s[1]], to.points[s[2]]));
        }
        largest = std::max(largest, double(nearest));
      }
    }
  }
  *spacing = step;
  return largest;
}

CertifiedHausdorffOptions absolute(double tolerance) {
  CertifiedHausdorffOptions options;
  options.tolerance = tolerance;
  options.relative = false;
  return options;
}

TEST(CertifiedDistance, BoundsContainAnIndependentReference) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  const auto point = [&] {
    return Eigen::Vector3d(coordinate(random), coordinate(random), coordinate(random));
  };
  for (int trial = 0; trial < 20000; ++trial) {
    const Eigen::Vector3d a = point(), b = point(), p = point();
    // Every fifth triangle is a sliver or a segment.
    const Eigen::Vector3d c =
        trial % 5 == 0 ? Eigen::Vector3d(a + 0.5 * (b - a) + 1e-9 * point()) : point();
    const long double reference = referenceDistance(p, a, b, c);
    const detail::CertifiedDistance bounds = detail::triangleDistanceBounds(p, a, b, c);
    ASSERT_LE(bounds.lower, reference) << trial;
    ASSERT_GE(bounds.upper, reference) << trial;
    // Tight up to the conditioning of the closest point (thin triangles lose a few digits).
    ASSERT_LE(bounds.upper - bounds.lower, 1e-10) << trial;
  }
}

TEST(MeshHausdorff, AMeshAgainstItselfIsZero) {
  const HausdorffShape sphere = sphereShape(1.0, 3);
  const CertifiedHausdorff result = certifiedHausdorff(sphere, sphere, absolute(1e-9));
  EXPECT_EQ(result.lower, 0.0);
  EXPECT_LE(result.upper, 1e-9);
  EXPECT_TRUE(result.aToB.converged && result.bToA.converged);
}

TEST(MeshHausdorff, ATranslatedBoxIsTheTranslationAway) {
  // Every coordinate of the translation points outward at the corner (1, 1, 1), whose nearest
  // point on the unmoved box is that corner; no point moves farther than |t|.
  const Eigen::Vector3d translation(0.1, 0.2, 0.3);
  const HausdorffShape box = boxShape({0, 0, 0}, {1, 1, 1});
  HausdorffShape moved = box;
  for (Eigen::Vector3d& point : moved.points) point += translation;
  const CertifiedHausdorff result = certifiedHausdorff(box, moved, absolute(1e-10));
  EXPECT_LE(result.lower, translation.norm());
  EXPECT_GE(result.upper, translation.norm());
  EXPECT_LE(result.upper - result.lower, 1e-10);
}

TEST(MeshHausdorff, BoxAgainstBoxByHand) {
  // A = [0,1]^3, B = [0,2] x [0,1]^2. h(B -> A) = 1: B's face x = 2 is 1 from A's face x = 1.
  // h(A -> B) = 1/2: A's face x = 1 lies inside B, its centre 1/2 from B's faces y, z = 0, 1.
  const HausdorffShape a = boxShape({0, 0, 0}, {1, 1, 1});
  const HausdorffShape b = boxShape({0, 0, 0}, {2, 1, 1});
  const CertifiedHausdorff result = certifiedHausdorff(a, b, absolute(1e-9));
  EXPECT_LE(result.aToB.lower, 0.5);
  EXPECT_GE(result.aToB.upper, 0.5);
  EXPECT_LE(result.aToB.upper - result.aToB.lower, 1e-9);
  EXPECT_NEAR(result.aToB.witness.x(), 1.0, 1e-6);
  EXPECT_NEAR(result.aToB.witness.y(), 0.5, 1e-4);
  EXPECT_NEAR(result.aToB.witness.z(), 0.5, 1e-4);
  EXPECT_LE(result.bToA.lower, 1.0);
  EXPECT_GE(result.bToA.upper, 1.0);
  EXPECT_LE(result.bToA.upper - result.bToA.lower, 1e-9);
  EXPECT_FALSE(result.aToBIsLarger);
  EXPECT_GT(result.aToB.primitivesRefined, 0u);
}

TEST(MeshHausdorff, NestedSpheresAreTheRadiusGapToTheChordError) {
  // Each tessellation lies between radius r c and r, c the smallest distance of a face's plane
  // from the centre (unit sphere). So H lies in [r2 - r1, r2 - r1 c].
  const test::UnitIcosphere unit = test::unitIcosphere(2);
  double c = 1.0;
  for (const TriangleMesh::Triangle& t : unit.triangles) {
    const Eigen::Vector3d& a = unit.positions[t[0]];
    const Eigen::Vector3d normal =
        (unit.positions[t[1]] - a).cross(unit.positions[t[2]] - a).normalized();
    c = std::min(c, std::abs(normal.dot(a)));
  }
  const double r1 = 1.0, r2 = 1.5;
  const CertifiedHausdorff result =
      certifiedHausdorff(sphereShape(r1, 2), sphereShape(r2, 2), absolute(1e-8));
  EXPECT_GE(result.upper, r2 - r1);
  EXPECT_LE(result.lower, r2 - r1 * c);
  EXPECT_LE(result.upper - result.lower, 1e-8);
  EXPECT_TRUE(result.aToB.converged && result.bToA.converged);
}

TEST(MeshHausdorff, RandomSmallPairsAgreeWithBruteForce) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  std::uniform_int_distribution<int> count(1, 4);
  const auto randomShape = [&] {
    HausdorffShape shape;
    const int triangles = count(random);
    for (int t = 0; t < triangles; ++t) {
      for (int k = 0; k < 3; ++k) {
        shape.points.emplace_back(coordinate(random), coordinate(random), coordinate(random));
      }
      const auto first = static_cast<std::uint32_t>(3 * t);
      shape.triangles.push_back({first, first + 1, first + 2});
    }
    return shape;
  };
  for (int pair = 0; pair < 1000; ++pair) {
    const HausdorffShape a = randomShape(), b = randomShape();
    const CertifiedHausdorff result = certifiedHausdorff(a, b, absolute(1e-7));
    double spacingA = 0.0, spacingB = 0.0;
    const double sampledAB = sampledDirected(a, b, 12, &spacingA);
    const double sampledBA = sampledDirected(b, a, 12, &spacingB);
    // The bracket contains the truth, which lies in [sampled, sampled + spacing].
    ASSERT_GE(result.aToB.upper, sampledAB) << pair;
    ASSERT_LE(result.aToB.lower, sampledAB + spacingA) << pair;
    ASSERT_GE(result.bToA.upper, sampledBA) << pair;
    ASSERT_LE(result.bToA.lower, sampledBA + spacingB) << pair;
    ASSERT_LE(result.upper - result.lower, 1e-7) << pair;
    // The witness attains the lower bound.
    long double witnessDistance = INFINITY;
    for (const TriangleIndices& t : b.triangles) {
      witnessDistance = std::min(
          witnessDistance,
          referenceDistance(result.aToB.witness, b.points[t[0]], b.points[t[1]], b.points[t[2]]));
    }
    ASSERT_GE(double(witnessDistance), result.aToB.lower - 1e-12) << pair;
  }
}

TEST(MeshHausdorff, PointsAgainstAMeshAreTheirLargestDistance) {
  const HausdorffShape box = boxShape({0, 0, 0}, {1, 1, 1});
  const Points cloud = {{0.5, 0.5, 0.5}, {2.0, 0.5, 0.5}, {0.2, 0.1, 0.9}, {1.0, 1.0, 1.0}};
  const CertifiedHausdorff result =
      certifiedHausdorff(hausdorffShapeOfPoints(cloud), box, absolute(1e-9));
  EXPECT_LE(result.aToB.lower, 1.0);  // (2, .5, .5) is 1 from the face x = 1
  EXPECT_GE(result.aToB.upper, 1.0);
  EXPECT_LE(result.aToB.upper - result.aToB.lower, 1e-9);
  ASSERT_EQ(result.aToB.pointDistances.size(), cloud.size());
  EXPECT_NEAR(result.aToB.pointDistances[0], 0.5, 1e-12);
  EXPECT_NEAR(result.aToB.pointDistances[2], 0.1, 1e-12);
  // The box's farthest point from the four points: brute force over a fine grid of its faces.
  double spacing = 0.0;
  const double sampled = sampledDirected(box, hausdorffShapeOfPoints(cloud), 60, &spacing);
  EXPECT_GE(result.bToA.upper, sampled);
  EXPECT_LE(result.bToA.lower, sampled + spacing);
}

TEST(MeshHausdorff, TheSameForAnyNumberOfThreads) {
  const HausdorffShape a = sphereShape(1.0, 3);
  HausdorffShape b = sphereShape(1.02, 2);
  for (Eigen::Vector3d& point : b.points) point.x() *= 1.1;
  const auto run = [&] { return certifiedHausdorff(a, b, absolute(1e-9)); };
  const CertifiedHausdorff one = test::withThreads(1, run);
  const CertifiedHausdorff two = test::withThreads(2, run);
  for (const auto& [x, y] : {std::pair(&one.aToB, &two.aToB), std::pair(&one.bToA, &two.bToA)}) {
    EXPECT_EQ(x->lower, y->lower);
    EXPECT_EQ(x->upper, y->upper);
    EXPECT_EQ(x->witness, y->witness);
    EXPECT_EQ(x->witnessClosest, y->witnessClosest);
    EXPECT_EQ(x->primitivesRefined, y->primitivesRefined);
    EXPECT_EQ(x->pointDistances, y->pointDistances);
  }
  EXPECT_GT(one.aToB.primitivesRefined, 0u);
}

TEST(MeshHausdorff, ACurveAgainstASurfaceItLiesOn) {
  // The bilinear square z = 0, [0,1]^2 as a biquadratic B-spline, and its diagonal as a cubic.
  Points grid;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) grid.emplace_back(0.5 * i, 0.5 * j, 0.0);
  }
  const BSplineSurface square = BSplineSurface::clamped(2, 2, 3, 3, grid);
  const BSplineCurve diagonal =
      BSplineCurve::clamped(3, {{0, 0, 0}, {0.3, 0.3, 0}, {0.6, 0.6, 0}, {1, 1, 0}});
  const HausdorffShape curve = hausdorffShapeOfCurve(diagonal, 1e-9);
  const HausdorffShape surface = hausdorffShapeOfSurface(square, 1e-9);
  const DirectedHausdorffBracket onIt = directedHausdorff(curve, surface, 1e-8);
  EXPECT_LE(onIt.upper, 1e-8);
  // The square's farthest points from the diagonal are the corners (1, 0) and (0, 1).
  const DirectedHausdorffBracket back = directedHausdorff(surface, curve, 1e-8);
  EXPECT_LE(back.lower, std::sqrt(0.5));
  EXPECT_GE(back.upper, std::sqrt(0.5));
  EXPECT_LE(back.upper - back.lower, 1e-8);
}

TEST(MeshHausdorff, BezierNetsAreMeasuredExactly) {
  // The parabola y = 4 t (1 - t), x = 2 t (a quadratic Bézier curve) against the segment from
  // (0, 0) to (2, 0): its apex (1, 1) is farthest, at distance 1.
  HausdorffShape parabola;
  parabola.nets.push_back({2, 0, {{0, 0, 0}, {1, 2, 0}, {2, 0, 0}}});
  HausdorffShape segment;
  segment.points = {{0, 0, 0}, {2, 0, 0}};
  segment.triangles = {{0, 1, 1}};
  const DirectedHausdorffBracket curve = directedHausdorff(parabola, segment, 1e-9);
  EXPECT_LE(curve.lower, 1.0);
  EXPECT_GE(curve.upper, 1.0);
  EXPECT_LE(curve.upper - curve.lower, 1e-9);
  EXPECT_NEAR(curve.witness.x(), 1.0, 1e-4);
  EXPECT_TRUE(curve.converged);

  // A biquadratic bump z = 2 (2s(1-s)) (2t(1-t)) over the unit square against the square: the
  // top (1/2, 1/2, 1/2) is farthest, at distance 1/2.
  BezierNet bump{2, 2, {}};
  for (int a = 0; a <= 2; ++a) {
    for (int b = 0; b <= 2; ++b)
      bump.controls.emplace_back(0.5 * a, 0.5 * b, a == 1 && b == 1 ? 2.0 : 0.0);
  }
  HausdorffShape patch;
  patch.nets.push_back(bump);
  HausdorffShape square;
  square.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  square.triangles = {{0, 1, 3}, {0, 3, 2}};
  const DirectedHausdorffBracket surface = directedHausdorff(patch, square, 1e-9);
  EXPECT_LE(surface.lower, 0.5);
  EXPECT_GE(surface.upper, 0.5);
  EXPECT_LE(surface.upper - surface.lower, 1e-9);
  EXPECT_NEAR(surface.witness.z(), 0.5, 1e-6);

  // The same bump from a B-spline: nets alone (maxError 0) need no tessellation.
  Points grid;
  for (const Eigen::Vector3d& point : bump.controls) grid.push_back(point);
  const HausdorffShape spline =
      hausdorffShapeOfSurface(BSplineSurface::clamped(2, 2, 3, 3, grid), 0.0);
  EXPECT_TRUE(spline.triangles.empty());
  ASSERT_EQ(spline.nets.size(), 1u);
  const DirectedHausdorffBracket again = directedHausdorff(spline, square, 1e-9);
  EXPECT_EQ(again.lower, surface.lower);
  EXPECT_EQ(again.upper, surface.upper);
  test::expectInputError([&] { directedHausdorff(square, spline, 1e-6); },
                         {"without a tessellation"});
}

TEST(HausdorffShape, TheTessellationErrorBoundHolds) {
  // A curved bicubic patch: every dense sample of the exact surface lies within the certified
  // error of the triangles.
  std::mt19937 random(3);
  std::uniform_real_distribution<double> bump(-0.3, 0.3);
  Points grid;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) grid.emplace_back(0.25 * i, 0.25 * j, bump(random));
  }
  const BSplineSurface patch = BSplineSurface::clamped(3, 3, 5, 5, grid);
  const HausdorffShape shape = hausdorffShapeOfSurface(patch, 1e-3);
  EXPECT_LE(shape.approximationError, 1.001e-3);
  const Points samples = patch.sample(17, 17);
  double worst = 0.0;
  for (const Eigen::Vector3d& sample : samples) {
    long double nearest = INFINITY;
    for (const TriangleIndices& t : shape.triangles) {
      nearest = std::min(nearest, referenceDistance(sample, shape.points[t[0]], shape.points[t[1]],
                                                    shape.points[t[2]]));
    }
    worst = std::max(worst, double(nearest));
  }
  EXPECT_LE(worst, shape.approximationError);
  EXPECT_GT(worst, 0.0);
  const BSplineCurve curve =
      BSplineCurve::clamped(3, {{0, 0, 0}, {1, 2, 0}, {2, -1, 1}, {3, 0, 0}});
  const HausdorffShape polyline = hausdorffShapeOfCurve(curve, 1e-4);
  double curveWorst = 0.0;
  for (const Eigen::Vector3d& sample : curve.sample(401)) {
    long double nearest = INFINITY;
    for (const TriangleIndices& t : polyline.triangles) {
      nearest = std::min(nearest, referenceDistance(sample, polyline.points[t[0]],
                                                    polyline.points[t[1]], polyline.points[t[2]]));
    }
    curveWorst = std::max(curveWorst, double(nearest));
  }
  EXPECT_LE(curveWorst, polyline.approximationError);
}

TEST(MeshHausdorff, LimitsStopWithAValidBracketAndAWarning) {
  const HausdorffShape a = boxShape({0, 0, 0}, {1, 1, 1});
  const HausdorffShape b = boxShape({0, 0, 0}, {2, 1, 1});
  for (const bool byBytes : {false, true}) {
    CertifiedHausdorffOptions options = absolute(1e-12);
    if (byBytes) {
      options.maxPieceBytes = 4000;
    } else {
      options.maxPieces = 8;
    }
    const DirectedHausdorffBracket bracket = directedHausdorff(a, b, 1e-12, options);
    EXPECT_FALSE(bracket.converged);
    EXPECT_NE(bracket.warning.find("limit of pieces"), std::string::npos) << bracket.warning;
    EXPECT_LE(bracket.lower, 0.5);  // h(A -> B) = 1/2, worked by hand above
    EXPECT_GE(bracket.upper, 0.5);
  }
  // A stretched sphere against a round one needs deep refinement near its tips.
  const HausdorffShape round = sphereShape(1.0, 3);
  HausdorffShape stretched = sphereShape(1.02, 2);
  for (Eigen::Vector3d& point : stretched.points) point.x() *= 1.1;
  const DirectedHausdorffBracket full = directedHausdorff(round, stretched, 1e-10);
  ASSERT_TRUE(full.converged);
  CertifiedHausdorffOptions shallow = absolute(1e-10);
  shallow.maxDepth = 1;
  const DirectedHausdorffBracket bracket = directedHausdorff(round, stretched, 1e-10, shallow);
  EXPECT_FALSE(bracket.converged);
  EXPECT_NE(bracket.warning.find("subdivision limit"), std::string::npos) << bracket.warning;
  EXPECT_LE(bracket.lower, full.upper);
  EXPECT_GE(bracket.upper, full.lower);
}

TEST(MeshHausdorff, LooseSecondDirectionKeepsTheTwoSidedBracket) {
  // H(B, A) with B = [0,2] x [0,1]^2, A = [0,1]^3: h(B -> A) = 1 decides it; h(A -> B) = 1/2 need
  // only be shown to be below 1.
  const HausdorffShape a = boxShape({0, 0, 0}, {1, 1, 1});
  const HausdorffShape b = boxShape({0, 0, 0}, {2, 1, 1});
  CertifiedHausdorffOptions loose = absolute(1e-9);
  loose.tightDirections = false;
  const CertifiedHausdorff tight = certifiedHausdorff(b, a, absolute(1e-9));
  const CertifiedHausdorff quick = certifiedHausdorff(b, a, loose);
  EXPECT_LE(quick.lower, 1.0);
  EXPECT_GE(quick.upper, 1.0);
  EXPECT_LE(quick.upper - quick.lower, 1e-9);
  EXPECT_LE(quick.bToA.lower, 0.5);  // still a bracket of h(A -> B), a wider one
  EXPECT_GE(quick.bToA.upper, 0.5);
  EXPECT_LE(quick.bToA.upper, 1.0 + 1e-9);
  EXPECT_LT(quick.bToA.primitivesRefined, tight.bToA.primitivesRefined);
}

TEST(MeshHausdorff, BadInputIsRefusedByName) {
  const HausdorffShape box = boxShape({0, 0, 0}, {1, 1, 1});
  test::expectInputError([&] { certifiedHausdorff(HausdorffShape{}, box); }, {"no primitives"});
  HausdorffShape broken = box;
  broken.points[3].x() = std::nan("");
  test::expectInputError([&] { certifiedHausdorff(box, broken); }, {"non-finite"});
  test::expectInputError([&] { certifiedHausdorff(box, box, absolute(0.0)); }, {"tolerance"});
  test::expectInputError([&] { certifiedHausdorff(box, box, absolute(-1.0)); }, {"tolerance"});
  test::expectInputError([&] { certifiedHausdorff(box, box, absolute(1e-30)); },
                         {"double precision"});
  test::expectInputError([&] { hausdorffShapeOfPoints({}); }, {"empty"});
  test::expectInputError([&] { hausdorffShapeOfMesh(TriangleMesh{}); }, {"no triangles"});
}

}  // namespace
}  // namespace d2vdb
