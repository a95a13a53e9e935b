// Generated initial surfaces: the circle floors of periodic cubics (published values), exact plane
// sheets, cylinders and tori against the analytic shapes, placement around sampled shapes, and the
// layout errors the command reports.
#include "d2vdb/fit/InitialSurface.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "FitTestSupport.h"
#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

TEST(InitialSurface, PeriodicCubicCircleFloorsMatchThePublishedValues) {
  // Uniform periodic cubics with n control points on a scaled regular n-gon approximate a circle
  // of radius 1 to these maximum errors (error ~ n^-4).
  for (const auto& [count, floor] :
       {std::pair{6, 2.04e-3}, std::pair{8, 5.76e-4}, std::pair{12, 1.05e-4},
        std::pair{16, 3.22e-5}, std::pair{32, 1.95e-6}}) {
    const CircleFit fit = periodicCircleFit(3, count);
    EXPECT_NEAR(fit.relativeError, floor, 0.01 * floor) << count;
    EXPECT_GT(fit.polygonScale, 1.0);
  }
  EXPECT_THROW(periodicCircleFit(3, 3), InputError);
}

TEST(InitialSurface, PlaneSheetIsExactAndLinearlyParametrized) {
  SurfaceLayout layout;
  layout.degreeU = 3;
  layout.degreeV = 2;
  layout.countU = 7;
  layout.countV = 4;
  const Eigen::Vector3d origin(1, 2, 3), edgeU(2, 0.5, 0), edgeV(-0.3, 1, 0.4);
  const BSplineSurface sheet = planeSheet(origin, edgeU, edgeV, layout);
  for (const double s : {0.0, 0.13, 0.5, 0.77, 1.0}) {
    for (const double t : {0.0, 0.31, 1.0}) {
      EXPECT_LT((sheet.evaluate(s, t) - (origin + s * edgeU + t * edgeV)).norm(), 1e-14);
    }
  }
  EXPECT_THROW(planeSheet(origin, edgeU, 2.0 * edgeU, layout), InputError);
  layout.closedU = true;
  EXPECT_THROW(planeSheet(origin, edgeU, edgeV, layout), InputError);
}

TEST(InitialSurface, CylinderAndTorusAreTheCircleFitsTensorProducts) {
  SurfaceLayout cylinderLayout;
  cylinderLayout.countU = 12;
  cylinderLayout.countV = 4;
  cylinderLayout.closedU = true;
  const Eigen::Vector3d axis = Eigen::Vector3d(0.2, -0.4, 1.0).normalized();
  const BSplineSurface cylinder =
      cylinderSurface(Eigen::Vector3d(1, 0, 0), 2.0 * axis, 0.7, cylinderLayout);
  double worst = 0.0;
  for (const Eigen::Vector3d& p : cylinder.sample(241, 9)) {
    const Eigen::Vector3d offset = p - Eigen::Vector3d(1, 0, 0);
    worst = std::max(worst, std::abs((offset - offset.dot(axis) * axis).norm() - 0.7));
  }
  EXPECT_NEAR(worst, 0.7 * periodicCircleFit(3, 12).relativeError, 1e-3 * worst);
  EXPECT_NEAR((cylinder.evaluate(0.3, 1.0) - cylinder.evaluate(0.3, 0.0)).dot(axis), 2.0, 1e-12);

  SurfaceLayout torusLayout;
  torusLayout.countU = 16;
  torusLayout.countV = 12;
  torusLayout.closedU = torusLayout.closedV = true;
  const double major = 2.0, minor = 0.5;
  const BSplineSurface torus =
      torusSurface(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::UnitZ(), major, minor, torusLayout);
  worst = 0.0;
  for (const Eigen::Vector3d& p : torus.sample(321, 241)) {
    const double radial = Eigen::Vector2d(p.x(), p.y()).norm() - major;
    worst = std::max(worst, std::abs(std::hypot(radial, p.z() - 1.0) - minor));
  }
  const double bound = (major + minor) * periodicCircleFit(3, 16).relativeError +
                       minor * periodicCircleFit(3, 12).relativeError;
  EXPECT_LE(worst, bound * 1.001);
  EXPECT_GT(worst, 0.5 * bound);
}

TEST(InitialSurface, PlacedAroundSampledShapes) {
  std::mt19937 engine(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d shift(0.5, -1, 2);
  // A 3 x 1 rectangle (rotated 25 degrees in its plane, then in space).
  std::vector<Eigen::Vector3d> rectangle;
  const double tilt = 25.0 * test::kTwoPi / 360.0;
  for (int i = 0; i < 4000; ++i) {
    const double x = 3.0 * unit(engine), y = unit(engine);
    rectangle.push_back(rotation * Eigen::Vector3d(x * std::cos(tilt) - y * std::sin(tilt),
                                                   x * std::sin(tilt) + y * std::cos(tilt), 0.0) +
                        shift);
  }
  InitialSurfaceOptions options;
  options.layout.countU = 6;
  options.layout.countV = 4;
  const BSplineSurface sheet = initialSurfaceAround(rectangle, options);
  EXPECT_NEAR((sheet.evaluate(1, 0) - sheet.evaluate(0, 0)).norm(), 3.0, 0.01);
  EXPECT_NEAR((sheet.evaluate(0, 1) - sheet.evaluate(0, 0)).norm(), 1.0, 0.01);
  const Eigen::Vector3d corner = rotation.transpose() * (sheet.evaluate(0, 0) - shift);
  EXPECT_NEAR(std::abs(corner.z()), 0.0, 1e-12);

  // A torus with radii 2 and 0.5 about a tilted axis, sampled by area.
  const Eigen::Vector3d axis = rotation.col(2);
  std::vector<Eigen::Vector3d> torusPoints;
  while (torusPoints.size() < 20000) {
    const double a = test::kTwoPi * unit(engine), b = test::kTwoPi * unit(engine);
    if (unit(engine) * 2.5 > 2.0 + 0.5 * std::cos(b)) continue;  // area weighting
    torusPoints.push_back(rotation * Eigen::Vector3d((2 + 0.5 * std::cos(b)) * std::cos(a),
                                                     (2 + 0.5 * std::cos(b)) * std::sin(a),
                                                     0.5 * std::sin(b)) +
                          shift);
  }
  options.shape = InitialSurfaceShape::Torus;
  options.layout.closedU = options.layout.closedV = true;
  options.layout.countU = 12;
  options.layout.countV = 8;
  const BSplineSurface torus = initialSurfaceAround(torusPoints, options);
  double worst = 0.0;
  for (const Eigen::Vector3d& p : torus.sample(60, 40)) {
    const Eigen::Vector3d local = rotation.transpose() * (p - shift);
    worst = std::max(worst, std::abs(std::hypot(local.head<2>().norm() - 2.0, local.z()) - 0.5));
  }
  EXPECT_LT(worst, 0.1);  // the estimates: major radius 2 + r^2 / 4R, minor radius ~ 0.5
  (void)axis;

  // A cylinder of radius 1 and height 3, sampled on a regular grid (so that its principal axes
  // are exact: random samples tilt the axis by about their covariance noise).
  std::vector<Eigen::Vector3d> cylinderPoints;
  for (int i = 0; i < 100; ++i) {
    for (int j = 0; j <= 60; ++j) {
      const double a = test::kTwoPi * i / 100;
      cylinderPoints.push_back(rotation * Eigen::Vector3d(std::cos(a), std::sin(a), 0.05 * j) +
                               shift);
    }
  }
  options.shape = InitialSurfaceShape::Cylinder;
  options.layout.closedV = false;
  const BSplineSurface cylinder = initialSurfaceAround(cylinderPoints, options);
  for (const Eigen::Vector3d& p : cylinder.sample(40, 5)) {
    const Eigen::Vector3d local = rotation.transpose() * (p - shift);
    EXPECT_NEAR(local.head<2>().norm(), 1.0, 0.01);
    EXPECT_GT(local.z(), -1e-9);
    EXPECT_LT(local.z(), 3.0 + 1e-9);
  }
}

TEST(InitialSurface, BadLayoutsAndPointsAreRejected) {
  SurfaceLayout layout;
  layout.countU = 3;  // degree 3 needs 4
  EXPECT_THROW(layout.validate(), InputError);
  layout.countU = 4;
  layout.closedU = true;
  layout.degreeV = 16;
  EXPECT_THROW(layout.validate(), InputError);
  layout.degreeV = 3;
  EXPECT_NO_THROW(layout.validate());
  InitialSurfaceOptions options;
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(i, 2 * i, 0);
  EXPECT_THROW(initialSurfaceAround(line, options), InputError);
  EXPECT_THROW(initialSurfaceAround({}, options), InputError);
  line.push_back(Eigen::Vector3d(std::nan(""), 0, 0));
  EXPECT_THROW(initialSurfaceAround(line, options), InputError);
  EXPECT_THROW(torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0, 2.0,
                            SurfaceLayout{3, 3, 8, 8, true, true}),
               InputError);
  EXPECT_THROW(cylinderSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0,
                               SurfaceLayout{3, 3, 8, 8, true, true}),
               InputError);
}

}  // namespace
}  // namespace d2vdb
