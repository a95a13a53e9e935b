#include "d2vdb/spline/BezierCurve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "d2vdb/core/Error.h"
#include "spline/SplineTestSupport.h"

namespace {

using d2vdb::BezierCurve;
using Eigen::Vector3d;

Vector3d explicitSum(const std::vector<Vector3d>& points, double t) {
  const int n = static_cast<int>(points.size()) - 1;
  Vector3d value = Vector3d::Zero();
  for (int i = 0; i <= n; ++i) {
    value += points[static_cast<std::size_t>(i)] * d2vdb::test::binomial(n, i) * std::pow(t, i) *
             std::pow(1.0 - t, n - i);
  }
  return value;
}

TEST(BezierCurve, EvaluationMatchesExplicitBernsteinSum) {
  std::mt19937 rng(21);
  for (int degree = 0; degree <= 10; ++degree) {
    const std::vector<Vector3d> points = d2vdb::test::randomPoints(rng, degree + 1);
    const BezierCurve curve(points);
    EXPECT_EQ(curve.degree(), degree);
    EXPECT_EQ(curve.controlPointCount(), degree + 1);
    for (int k = 0; k <= 10; ++k) {
      EXPECT_LT((curve.evaluate(k / 10.0) - explicitSum(points, k / 10.0)).norm(), 1e-12);
    }
    EXPECT_EQ(curve.evaluate(0.0), points.front());
    EXPECT_LT((curve.evaluate(1.0) - points.back()).norm(), 1e-15);
  }
}

TEST(BezierCurve, SubdivisionHalvesReproduceTheCurve) {
  std::mt19937 rng(22);
  for (int degree = 1; degree <= 7; ++degree) {
    const BezierCurve curve(d2vdb::test::randomPoints(rng, degree + 1));
    const double split = d2vdb::test::randomParameter(rng, 0.1, 0.9);
    const auto [left, right] = curve.subdivide(split);
    for (int k = 0; k <= 10; ++k) {
      const double s = k / 10.0;
      EXPECT_LT((left.evaluate(s) - curve.evaluate(split * s)).norm(), 1e-12);
      EXPECT_LT((right.evaluate(s) - curve.evaluate(split + s * (1.0 - split))).norm(), 1e-12);
    }
    const BezierCurve piece = curve.restricted(0.25, 0.6);
    for (int k = 0; k <= 10; ++k) {
      const double s = k / 10.0;
      EXPECT_LT((piece.evaluate(s) - curve.evaluate(0.25 + 0.35 * s)).norm(), 1e-12);
    }
  }
}

TEST(BezierCurve, HodographMatchesCentralDifferenceAndElevationKeepsTheCurve) {
  std::mt19937 rng(23);
  for (int degree = 0; degree <= 7; ++degree) {
    const BezierCurve curve(d2vdb::test::randomPoints(rng, degree + 1));
    const BezierCurve derivative = curve.derivative();
    const BezierCurve elevated = curve.elevated(3);
    EXPECT_EQ(elevated.degree(), degree + 3);
    const double h = 1e-5;
    for (int k = 0; k <= 10; ++k) {
      const double t = k / 10.0;
      const Vector3d difference = (curve.evaluate(t + h) - curve.evaluate(t - h)) / (2 * h);
      EXPECT_LT((derivative.evaluate(t) - difference).norm(), 1e-6);
      EXPECT_LT((elevated.evaluate(t) - curve.evaluate(t)).norm(), 1e-13);
    }
  }
}

TEST(BezierCurve, BoundsCoordinatesAndTranslation) {
  std::mt19937 rng(24);
  const BezierCurve curve(d2vdb::test::randomPoints(rng, 6));
  const Eigen::AlignedBox3d box = curve.controlPointBounds();
  const Vector3d offset(0.5, -1.0, 2.0);
  const BezierCurve moved = curve.translated(offset);
  for (int k = 0; k <= 40; ++k) {
    const double t = k / 40.0;
    const Vector3d point = curve.evaluate(t);
    EXPECT_TRUE(box.contains(point));
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(curve.coordinate(axis).evaluate(t), point[axis], 1e-13);
    }
    EXPECT_LT((moved.evaluate(t) - (point + offset)).norm(), 1e-13);
  }
  EXPECT_THROW(curve.coordinate(3), d2vdb::InputError);
}

// engine/README.md's worked example: quadratic Bézier (-1,0),(0,2),(1,0), p = (0,0). (C - p) . C'
// has the cubic Bernstein coefficients -2, 14/3, -14/3, 2; roots 1/2 and 1/2 -+ sqrt(2)/4, whose
// points
// (-+sqrt(2)/2, 1/2) are the closest points at distance sqrt(3)/2.
TEST(BezierCurve, DotProductGivesTheProjectionConditionOfTheDesignExample) {
  const BezierCurve curve(std::vector<Vector3d>{{-1, 0, 0}, {0, 2, 0}, {1, 0, 0}});
  const Vector3d p(0, 0, 0);
  const d2vdb::BernsteinPolynomial condition = dot(curve.translated(-p), curve.derivative());
  ASSERT_EQ(condition.degree(), 3);
  const double expected[] = {-2.0, 14.0 / 3.0, -14.0 / 3.0, 2.0};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(condition.coefficient(i), expected[i], 1e-14);
  const double root = 0.5 - std::sqrt(2.0) / 4.0;
  EXPECT_NEAR(condition.evaluate(root), 0.0, 1e-14);
  const Vector3d closest = curve.evaluate(root);
  EXPECT_NEAR(closest.x(), -std::sqrt(2.0) / 2.0, 1e-14);
  EXPECT_NEAR(closest.y(), 0.5, 1e-14);
  EXPECT_NEAR((closest - p).norm(), std::sqrt(3.0) / 2.0, 1e-14);
}

TEST(BezierCurve, DotProductMatchesPointwiseDotOfRandomCurves) {
  std::mt19937 rng(25);
  for (int trial = 0; trial < 20; ++trial) {
    const BezierCurve a(d2vdb::test::randomPoints(rng, 1 + trial % 6));
    const BezierCurve b(d2vdb::test::randomPoints(rng, 1 + (trial * 5) % 7));
    const d2vdb::BernsteinPolynomial product = dot(a, b);
    EXPECT_EQ(product.degree(), a.degree() + b.degree());
    for (int k = 0; k <= 10; ++k) {
      const double t = k / 10.0;
      EXPECT_NEAR(product.evaluate(t), a.evaluate(t).dot(b.evaluate(t)), 1e-12);
    }
  }
}

TEST(BezierCurve, RejectsInvalidControlPoints) {
  EXPECT_THROW(BezierCurve(std::vector<Vector3d>{}), d2vdb::InputError);
  EXPECT_THROW(BezierCurve(std::vector<Vector3d>(33, Vector3d::Zero())), d2vdb::InputError);
  EXPECT_THROW(BezierCurve(std::vector<Vector3d>{{0, 0, 0}, {std::nan(""), 0, 0}}),
               d2vdb::InputError);
}

}  // namespace
