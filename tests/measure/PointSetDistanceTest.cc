// Nearest-point distances to a point set (measure/PointSetDistance.h) against brute force: random
// clouds of several shapes (a volume, a flat sheet, a line, one point), queried inside and far
// outside their bounding boxes; the empty set answers +inf.
#include "d2vdb/measure/PointSetDistance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace d2vdb {
namespace {

double bruteForce(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& x) {
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : points) best = std::min(best, (p - x).squaredNorm());
  return std::sqrt(best);
}

TEST(PointSetDistance, EqualsBruteForceOnCloudsOfEveryShape) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto shapes = {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(2, 1, 0), Eigen::Vector3d(3, 0, 0),
                       Eigen::Vector3d(0, 0, 0)};
  for (const Eigen::Vector3d& extent : shapes) {
    std::vector<Eigen::Vector3d> points;
    const int count = extent.norm() > 0 ? 700 : 1;
    for (int i = 0; i < count; ++i) {
      points.emplace_back(extent.x() * unit(random), extent.y() * unit(random),
                          extent.z() * unit(random));
    }
    const PointSetDistance distance(points);
    for (int q = 0; q < 300; ++q) {
      const double reach = q < 250 ? 1.5 : 40.0;  // inside the box, then far away
      const Eigen::Vector3d x(reach * unit(random), reach * unit(random), reach * unit(random));
      EXPECT_EQ(distance(x), bruteForce(points, x)) << x.transpose();
    }
  }
}

TEST(PointSetDistance, EmptySetIsInfinitelyFar) {
  EXPECT_EQ(PointSetDistance({})(Eigen::Vector3d::Zero()), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace d2vdb
