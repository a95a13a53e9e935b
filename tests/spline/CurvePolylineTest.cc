// Drawing polylines of B-spline curves: point counts by polynomial pieces, and points on the
// curve against closed forms (a parabola, a straight line).
#include "d2vdb/spline/CurvePolyline.h"

#include "d2vdb/core/Error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <vector>

namespace {

using d2vdb::BSplineCurve;
using d2vdb::drawingPointCount;
using d2vdb::drawingPolylines;
using Eigen::Vector3d;

/// The quadratic Bézier (-1, 0), (0, 2), (1, 0) on [0, 1]: C(t) = (2t - 1, 4t(1 - t)), one piece.
BSplineCurve parabola() {
  return BSplineCurve::clamped(2, {{-1, 0, 0}, {0, 2, 0}, {1, 0, 0}}, 2);
}

/// A clamped cubic with `pieces` polynomial pieces (pieces + 3 collinear control points on the
/// x axis, equally spaced, so that C(t) = (t, 0, 0) on the domain [0, pieces]).
BSplineCurve cubicLine(int pieces) {
  std::vector<Vector3d> points;
  // Greville abscissae of the clamped uniform knot vector: the line is reproduced exactly.
  const int count = pieces + 3;
  std::vector<double> knots(3, 0.0);
  for (int i = 0; i <= pieces; ++i) knots.push_back(i);
  knots.insert(knots.end(), 3, static_cast<double>(pieces));
  for (int i = 0; i < count; ++i) {
    points.emplace_back((knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0, 0.0, 0.0);
  }
  return BSplineCurve::clamped(3, points, 3, {0.0, static_cast<double>(pieces)});
}

TEST(CurvePolyline, SixtyFourPointsPerPieceBetween512And20000) {
  EXPECT_EQ(drawingPointCount(parabola()), 512);
  EXPECT_EQ(drawingPointCount(cubicLine(8)), 512);
  EXPECT_EQ(drawingPointCount(cubicLine(9)), 576);
  EXPECT_EQ(drawingPointCount(cubicLine(20)), 1280);
  EXPECT_EQ(drawingPointCount(cubicLine(312)), 19968);
  EXPECT_EQ(drawingPointCount(cubicLine(313)), 20000);
  EXPECT_EQ(drawingPointCount(cubicLine(1000)), 20000);
  const BSplineCurve closed = BSplineCurve::closed(3, {{1, 0, 0},
                                                       {0, 1, 0},
                                                       {-1, 0, 0},
                                                       {0, -1, 0},
                                                       {1, 1, 0},
                                                       {2, 0, 0},
                                                       {1, -1, 0},
                                                       {0, -2, 0},
                                                       {-2, 0, 0},
                                                       {0, 2, 0},
                                                       {3, 3, 0}});
  EXPECT_EQ(drawingPointCount(closed), 11 * 64);  // one piece per unique control point
}

TEST(CurvePolyline, PointsLieOnTheCurveUniformlyInParameter) {
  const BSplineCurve curve = parabola();
  const std::vector<std::vector<Vector3d>> single = drawingPolylines({curve});
  ASSERT_EQ(single.size(), 1u);
  ASSERT_EQ(single[0].size(), 512u);
  for (std::size_t i = 0; i < single[0].size(); ++i) {
    const double t = static_cast<double>(i) / 511.0;
    EXPECT_NEAR(single[0][i].x(), 2.0 * t - 1.0, 1e-14) << i;
    EXPECT_NEAR(single[0][i].y(), 4.0 * t * (1.0 - t), 1e-14) << i;
    EXPECT_EQ(single[0][i].z(), 0.0) << i;
  }
  EXPECT_EQ(single[0].front(), Vector3d(-1, 0, 0));
  EXPECT_EQ(single[0].back(), Vector3d(1, 0, 0));
}

TEST(CurvePolyline, CurvesDrawnTogetherShareTheLargestCount) {
  const BSplineCurve curve = parabola();
  const BSplineCurve line = cubicLine(20);
  const std::vector<std::vector<Vector3d>> both = drawingPolylines({curve, line});
  ASSERT_EQ(both.size(), 2u);
  ASSERT_EQ(both[0].size(), 1280u);
  ASSERT_EQ(both[1].size(), 1280u);
  for (std::size_t i = 0; i < 1280; ++i) {
    const double t = static_cast<double>(i) / 1279.0;
    EXPECT_NEAR(both[0][i].y(), 4.0 * t * (1.0 - t), 1e-14) << i;
    EXPECT_NEAR(both[1][i].x(), 20.0 * t, 1e-12) << i;
    EXPECT_NEAR(both[1][i].y(), 0.0, 1e-15) << i;
  }
  EXPECT_TRUE(drawingPolylines({}).empty());
}

}  // namespace

TEST(CurvePolyline, SampledLengthConvergesFromBelowToTheParabolasArcLength) {
  // C(t) = (2t - 1, 4t(1 - t)): |C'(t)| = 2 sqrt(1 + (2 - 4t)^2), so the arc length is
  // int_0^2 sqrt(1 + u^2) du = sqrt(5) + asinh(2) / 2.
  const double exact = std::sqrt(5.0) + std::asinh(2.0) / 2.0;
  EXPECT_DOUBLE_EQ(d2vdb::sampledLength(parabola(), 2), 2.0);  // the chord
  const double coarse = d2vdb::sampledLength(parabola(), 1025);
  const double fine = d2vdb::sampledLength(parabola(), 2049);
  EXPECT_LT(coarse, exact);
  EXPECT_LT(fine, exact);
  EXPECT_NEAR(coarse, exact, 1e-5);
  // Second order: halving the spacing quarters the error.
  EXPECT_NEAR((exact - coarse) / (exact - fine), 4.0, 0.05);
  // A straight line is measured exactly.
  EXPECT_NEAR(d2vdb::sampledLength(cubicLine(5), 17), 5.0, 1e-12);
  EXPECT_THROW(d2vdb::sampledLength(parabola(), 1), d2vdb::InputError);
}
