// Exact B-spline surface targets: the hyperbolic paraboloid z = xy (a bilinear patch) against
// brute-force distances, its curvature (the SDM form is a third-order approximation of the squared
// distance), boundary footpoints and bad input.
#include "d2vdb/field/SurfaceTarget.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

/// z = xy over [0, 1]^2, exactly the bilinear patch with corners (0,0,0), (0,1,0), (1,0,0),
/// (1,1,1).
BSplineSurface hyperbolicParaboloid() {
  return BSplineSurface::clamped(1, 1, 2, 2,
                                 {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1, 0),
                                  Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 1)});
}

/// Distance to z = xy over [0, 1]^2 by a dense grid and a compass search (independent of the
/// spline code).
double bruteDistance(const Eigen::Vector3d& p) {
  const auto at = [&](double x, double y) {
    x = std::clamp(x, 0.0, 1.0);
    y = std::clamp(y, 0.0, 1.0);
    return (Eigen::Vector3d(x, y, x * y) - p).squaredNorm();
  };
  double best = 1e300, bx = 0, by = 0;
  for (int i = 0; i <= 200; ++i) {
    for (int j = 0; j <= 200; ++j) {
      const double d = at(i / 200.0, j / 200.0);
      if (d < best) best = d, bx = i / 200.0, by = j / 200.0;
    }
  }
  for (double h = 1.0 / 200; h > 1e-15;) {
    bool improved = false;
    for (const auto& [a, b] :
         {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}, std::pair{1, 1},
          std::pair{-1, -1}, std::pair{1, -1}, std::pair{-1, 1}}) {
      const double x = std::clamp(bx + a * h, 0.0, 1.0), y = std::clamp(by + b * h, 0.0, 1.0);
      const double d = at(x, y);
      if (d < best) {
        best = d, bx = x, by = y, improved = true;
        break;
      }
    }
    if (!improved) h *= 0.5;
  }
  return std::sqrt(best);
}

TEST(SurfaceTarget, DistancesAndCurvaturesOfTheHyperbolicParaboloid) {
  const SurfaceTarget target(hyperbolicParaboloid());
  std::mt19937 engine(2);
  std::uniform_real_distribution<double> inside(0.15, 0.85), offset(-0.1, 0.1);
  for (int trial = 0; trial < 30; ++trial) {
    const double x = inside(engine), y = inside(engine);
    const Eigen::Vector3d p = Eigen::Vector3d(x, y, x * y) +
                              Eigen::Vector3d(offset(engine), offset(engine), offset(engine));
    const Approximant a = target.approximantAt(p);
    ASSERT_EQ(a.flags & kFlagEndPoint, 0);
    EXPECT_NEAR(std::abs(a.distance), bruteDistance(p), 1e-12);
    EXPECT_LT((a.footpoint + a.distance * a.normal - p).norm(), 1e-12);
    // Curvatures of the graph z = xy at the footpoint: K = -1 / (1 + x^2 + y^2)^2 and mean
    // curvature H = -xy / (1 + x^2 + y^2)^(3/2) (sign of the upward normal).
    const double fx = a.footpoint.y(), fy = a.footpoint.x();
    const double w = 1.0 + fx * fx + fy * fy;
    EXPECT_NEAR(a.k1 * a.k2, -1.0 / (w * w), 1e-12);
    const double upward = a.normal.z() > 0 ? 1.0 : -1.0;
    // k = -(normal curvature), so k1 + k2 = -2 H for the upward normal, where
    // 2 H = (2 fx fy fxy) ... with fxx = fyy = 0, fxy = 1: 2H = -2 fx fy / w^(3/2).
    EXPECT_NEAR(upward * (a.k1 + a.k2), 2.0 * fx * fy / std::pow(w, 1.5), 1e-12);
  }
}

TEST(SurfaceTarget, TaylorApproximantOfTheSquaredDistanceIsThirdOrder) {
  // The unclamped Taylor approximant built from the answer (footpoint, frame, curvatures):
  // F(x) = sum_i d k_i / (1 + d k_i) ((x - s) . e_i)^2 + ((x - s) . n)^2 (on a saddle one weight
  // is negative, which the SDM form clamps to 0).
  const SurfaceTarget target(hyperbolicParaboloid());
  const Eigen::Vector3d p(0.4, 0.6, 0.24 + 0.05);
  const Approximant a = target.approximantAt(p);
  const double d = a.distance;
  const auto taylor = [&](const Eigen::Vector3d& x) {
    const Eigen::Vector3d r = x - a.footpoint;
    return d * a.k1 / (1 + d * a.k1) * std::pow(r.dot(a.tangent), 2) +
           d * a.k2 / (1 + d * a.k2) * std::pow(r.dot(a.bitangent()), 2) +
           std::pow(r.dot(a.normal), 2);
  };
  EXPECT_NEAR(taylor(p), d * d, 1e-15);
  EXPECT_NEAR(a.form(ErrorTerm::SDM)(p), d * d, 1e-15);
  const Eigen::Vector3d direction = Eigen::Vector3d(0.6, -0.5, 0.3).normalized();
  double previous = 0.0;
  for (const double h : {0.04, 0.02, 0.01}) {
    const Eigen::Vector3d q = p + h * direction;
    const double error = std::abs(taylor(q) - std::pow(bruteDistance(q), 2));
    if (previous > 0.0) {
      EXPECT_GT(previous / error, 6.5) << h;  // 8 for third order
    }
    previous = error;
  }
}

TEST(SurfaceTarget, FootpointsOnTheBoundaryArePointDistances) {
  const SurfaceTarget target(hyperbolicParaboloid());
  const Eigen::Vector3d p(1.3, 0.5, 0.7);  // beyond the x = 1 edge
  const Approximant a = target.approximantAt(p);
  EXPECT_NE(a.flags & kFlagEndPoint, 0);
  EXPECT_NEAR(a.distance, bruteDistance(p), 1e-12);
  EXPECT_NEAR(a.footpoint.x(), 1.0, 1e-15);
  EXPECT_LT((a.form(ErrorTerm::SDM).A - Eigen::Matrix3d::Identity()).norm(), 1e-15);
}

TEST(SurfaceTarget, BadInputIsRejected) {
  EXPECT_THROW(SurfaceTarget(BSplineSurface::clamped(
                   1, 1, 2, 2, std::vector<Eigen::Vector3d>(4, Eigen::Vector3d::Ones()))),
               InputError);
  const SurfaceTarget target(hyperbolicParaboloid());
  EXPECT_THROW(target.approximantAt(Eigen::Vector3d(9, 9, 9)), InputError);
  EXPECT_THROW(target.approximantAt(Eigen::Vector3d(std::nan(""), 0, 0)), InputError);
  EXPECT_THROW(SurfaceTarget(hyperbolicParaboloid(), -1.0), InputError);
}

}  // namespace
}  // namespace d2vdb
