// Curves shared by the measure tests: planar and spatial, open and closed, degrees 1 to 5.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <vector>

#include "d2vdb/core/MathConstants.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb::test {

/// A planar point (z = 0).
inline Eigen::Vector3d xy(double x, double y) {
  return {x, y, 0.0};
}

/// The two cubic Béziers of the worked example in Shtain's lecture on Chen et al. (2010).
inline BSplineCurve seedCurveA() {
  return BSplineCurve::clamped(3, {xy(193, 226), xy(227, 230), xy(297, 134), xy(421, 135)}, 2);
}
inline BSplineCurve seedCurveB() {
  return BSplineCurve::clamped(3, {xy(258, 481), xy(294, 438), xy(302, 268), xy(435, 213)}, 2);
}

/// The worked example's quadratic Bézier (-1, 0), (0, 2), (1, 0).
inline BSplineCurve seedQuadratic() {
  return BSplineCurve::clamped(2, {xy(-1, 0), xy(0, 2), xy(1, 0)}, 2);
}

/// A wavy planar clamped cubic with 4 spans.
inline BSplineCurve wavyCubic() {
  return BSplineCurve::clamped(
      3, {xy(0, 0), xy(1, 2), xy(2, -1), xy(3, 2.5), xy(4, -0.5), xy(5, 1.5), xy(6, 0)}, 2);
}

/// A planar clamped quartic with 4 spans crossing wavyCubic().
inline BSplineCurve planarQuartic() {
  return BSplineCurve::clamped(4,
                               {xy(-0.5, 1), xy(1, 0.5), xy(2, 2), xy(3.5, 0), xy(4.5, 1.5),
                                xy(5.5, -0.5), xy(6.5, 0.8), xy(7, 0.2)},
                               2);
}

/// A spatial quintic Bézier.
inline BSplineCurve spatialQuintic() {
  return BSplineCurve::clamped(
      5, {{0, 0, 0}, {1, 2, 1}, {2, -1, 2}, {3, 1, -1}, {4, 0, 1}, {5, 1, 0}}, 3);
}

/// A spatial clamped quadratic with 4 spans.
inline BSplineCurve spatialQuadratic() {
  return BSplineCurve::clamped(
      2, {{0, 1, 1}, {1, -1, 0}, {2.5, 1.5, 0.5}, {3, 0, 2}, {4.5, 0.5, -0.5}, {5, 2, 0.5}}, 3);
}

/// A closed (periodic) planar cubic, roughly an ellipse.
inline BSplineCurve closedCubic() {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 6; ++i) {
    const double angle = 2.0 * kPi * i / 6.0;
    points.push_back(xy(3.0 * std::cos(angle), 1.5 * std::sin(angle)));
  }
  return BSplineCurve::closed(3, points, 2);
}

/// A closed planar quadratic blob, offset from closedCubic().
inline BSplineCurve closedQuadraticBlob() {
  return BSplineCurve::closed(
      2,
      {xy(0.5, -1), xy(2.5, -0.5), xy(3, 1), xy(1, 2.2), xy(-1.5, 1.8), xy(-2.5, 0), xy(-1, -1.5)},
      2);
}

/// A planar polyline (degree 1) with corners.
inline BSplineCurve zigzag() {
  return BSplineCurve::clamped(
      1, {xy(0, 0), xy(1, 1.5), xy(2, 0.2), xy(3, 1.8), xy(4, 0.5), xy(5, 1)}, 2);
}

/// A planar cubic with a C0 corner: the interior knot 0.5 has multiplicity 3 = the degree.
inline BSplineCurve cubicWithCorner() {
  return BSplineCurve(
      KnotVector(3, {0, 0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1, 1}),
      {xy(0, 0), xy(0.5, 1), xy(1, 1.5), xy(1.5, 2), xy(2.5, 1), xy(3, 1.5), xy(4, 0.5)}, 2);
}

/// A closed spatial quartic.
inline BSplineCurve closedSpatialQuartic() {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 7; ++i) {
    const double angle = 2.0 * kPi * i / 7.0;
    points.push_back({2.0 * std::cos(angle), 2.0 * std::sin(angle), 0.8 * std::sin(2.0 * angle)});
  }
  return BSplineCurve::closed(4, points, 3);
}

/// A spatial cubic helix, two turns.
inline BSplineCurve helix() {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 12; ++i) {
    const double angle = 4.0 * kPi * i / 11.0;
    points.push_back({1.5 * std::cos(angle), 1.5 * std::sin(angle), 0.25 * angle - 1.5});
  }
  return BSplineCurve::clamped(3, points, 3);
}

/// A cubic with a zero-length span: four equal consecutive control points.
inline BSplineCurve cubicWithZeroLengthSpan() {
  return BSplineCurve::clamped(
      3, {xy(0, 0), xy(1, 1), xy(2, 0), xy(2, 0), xy(2, 0), xy(2, 0), xy(3, 1), xy(4, 0)}, 2);
}

/// The same curve traversed backwards (control points reversed, knots mirrored).
inline BSplineCurve reversed(const BSplineCurve& curve) {
  const std::vector<double>& knots = curve.knots().values();
  const double sum = curve.domain().start + curve.domain().end;
  std::vector<double> mirrored;
  for (auto it = knots.rbegin(); it != knots.rend(); ++it) mirrored.push_back(sum - *it);
  std::vector<Eigen::Vector3d> points(curve.controlPoints().rbegin(), curve.controlPoints().rend());
  return BSplineCurve(KnotVector(curve.degree(), mirrored), points, curve.dimension());
}

/// Every control point mapped by x -> scale x + offset.
inline BSplineCurve transformed(const BSplineCurve& curve, double scale,
                                const Eigen::Vector3d& offset) {
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3d& point : curve.controlPoints())
    points.push_back(scale * point + offset);
  return BSplineCurve(curve.knots(), points, offset.z() == 0.0 ? curve.dimension() : 3,
                      curve.isClosed());
}

}  // namespace d2vdb::test
