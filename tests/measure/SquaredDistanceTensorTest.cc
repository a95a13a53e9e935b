// The tensor-product Bernstein form of S(u, v) = |P(u) - Q(v)|^2.
#include <gtest/gtest.h>

#include <vector>

#include "d2vdb/measure/detail/SquaredDistanceTensor.h"

namespace {

using d2vdb::BezierCurve;
using d2vdb::detail::SquaredDistanceTensor;

TEST(SquaredDistanceTensor, MatchesDirectEvaluationAndBoundsIt) {
  const BezierCurve p(
      std::vector<Eigen::Vector3d>{{193, 226, 0}, {227, 230, 0}, {297, 134, 0}, {421, 135, 0}});
  const BezierCurve q(std::vector<Eigen::Vector3d>{{258, 481, 5}, {294, 438, -3}, {435, 213, 1}});
  const SquaredDistanceTensor tensor(p, q);
  EXPECT_EQ(tensor.degreeU(), 6);
  EXPECT_EQ(tensor.degreeV(), 4);
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      const double u = i / 20.0;
      const double v = j / 20.0;
      const double direct = (p.evaluate(u) - q.evaluate(v)).squaredNorm();
      EXPECT_NEAR(tensor.evaluate(u, v), direct, 1e-10 * direct);
      EXPECT_LE(tensor.minCoefficient(), direct + tensor.roundingBound());
      EXPECT_GE(tensor.maxCoefficient(), direct - tensor.roundingBound());
    }
  }
  // Corner coefficients interpolate: F_{0,0} = |P_0 - Q_0|^2.
  EXPECT_NEAR(tensor.coefficients()(0, 0), (p.controlPoint(0) - q.controlPoint(0)).squaredNorm(),
              1e-9);
  EXPECT_NEAR(tensor.coefficients()(6, 4), (p.controlPoint(3) - q.controlPoint(2)).squaredNorm(),
              1e-9);
}

TEST(SquaredDistanceTensor, IdenticalCurvesTouchZero) {
  // S vanishes on the diagonal, so the smallest coefficient (a lower bound) is at most zero;
  // coefficients of the non-negative S may well be negative.
  const BezierCurve p(std::vector<Eigen::Vector3d>{{0, 0, 0}, {1, 2, 0}, {3, -1, 1}});
  const SquaredDistanceTensor tensor(p, p);
  EXPECT_LE(tensor.minCoefficient(), 0.0);
  EXPECT_EQ(tensor.coefficients()(0, 0), 0.0);
  EXPECT_EQ(tensor.coefficients()(4, 4), 0.0);
  for (int i = 0; i <= 10; ++i) EXPECT_NEAR(tensor.evaluate(i / 10.0, i / 10.0), 0.0, 1e-13);
}

}  // namespace
