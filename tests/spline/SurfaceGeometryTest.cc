// Principal curvatures and directions of parametric surfaces against closed forms (sphere, torus)
// and a brute-force search over the normal curvature of every tangent direction (graphs).
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/spline/SurfaceGeometry.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

namespace d2vdb {
namespace {

// Sphere of radius R, S = R (cos v cos u, cos v sin u, sin v): Su x Sv points outward.
SurfaceDerivatives sphere(double radius, double u, double v) {
  const double cu = std::cos(u), su = std::sin(u), cv = std::cos(v), sv = std::sin(v);
  SurfaceDerivatives d;
  d.point = radius * Eigen::Vector3d(cv * cu, cv * su, sv);
  d.du = radius * Eigen::Vector3d(-cv * su, cv * cu, 0.0);
  d.dv = radius * Eigen::Vector3d(-sv * cu, -sv * su, cv);
  d.duu = radius * Eigen::Vector3d(-cv * cu, -cv * su, 0.0);
  d.duv = radius * Eigen::Vector3d(sv * su, -sv * cu, 0.0);
  d.dvv = radius * Eigen::Vector3d(-cv * cu, -cv * su, -sv);
  return d;
}

// Torus with radii R > r: S = ((R + r cos v) cos u, (R + r cos v) sin u, r sin v); v runs around
// the tube (v = 0 on the outer equator). Su x Sv points outward.
SurfaceDerivatives torus(double major, double minor, double u, double v) {
  const double cu = std::cos(u), su = std::sin(u), cv = std::cos(v), sv = std::sin(v);
  const double w = major + minor * cv;
  SurfaceDerivatives d;
  d.point = Eigen::Vector3d(w * cu, w * su, minor * sv);
  d.du = Eigen::Vector3d(-w * su, w * cu, 0.0);
  d.dv = Eigen::Vector3d(-minor * sv * cu, -minor * sv * su, minor * cv);
  d.duu = Eigen::Vector3d(-w * cu, -w * su, 0.0);
  d.duv = Eigen::Vector3d(minor * sv * su, -minor * sv * cu, 0.0);
  d.dvv = Eigen::Vector3d(-minor * cv * cu, -minor * cv * su, -minor * sv);
  return d;
}

TEST(SurfaceGeometry, SphereIsUmbilicWithCurvatureOneOverRadius) {
  for (const double v : {-1.2, -0.3, 0.0, 0.8}) {
    const SurfaceFrame frame = surfaceFrame(sphere(2.5, 0.7, v));
    ASSERT_TRUE(frame.regular);
    EXPECT_NEAR(frame.k1, 0.4, 1e-14);
    EXPECT_NEAR(frame.k2, 0.4, 1e-14);
    EXPECT_NEAR((frame.normal - frame.point / 2.5).norm(), 0.0, 1e-14);
    EXPECT_NEAR(frame.e1.cross(frame.e2).dot(frame.normal), 1.0, 1e-14);
  }
}

TEST(SurfaceGeometry, TorusHasTheTubeAndTheRingCurvatures) {
  const double major = 2.0, minor = 0.5;
  for (double v = -kPi; v < kPi; v += 0.37) {
    const SurfaceFrame frame = surfaceFrame(torus(major, minor, 0.3, v));
    ASSERT_TRUE(frame.regular);
    const double ring = std::cos(v) / (major + minor * std::cos(v));
    EXPECT_NEAR(frame.k1, 1.0 / minor, 1e-13);
    EXPECT_NEAR(frame.k2, ring, 1e-13);
    // e1 runs around the tube: along Sv.
    const Eigen::Vector3d tube = torus(major, minor, 0.3, v).dv.normalized();
    EXPECT_NEAR(std::abs(frame.e1.dot(tube)), 1.0, 1e-12);
    EXPECT_NEAR(frame.e1.cross(frame.e2).dot(frame.normal), 1.0, 1e-14);
    const Eigen::Vector3d outward =
        (frame.point - major * Eigen::Vector3d(std::cos(0.3), std::sin(0.3), 0.0)) / minor;
    EXPECT_NEAR((frame.normal - outward).norm(), 0.0, 1e-13);
  }
}

// Graph z = f(x, y) of a random cubic, parametrised by (x, y) with skewed, scaled parameters so
// that the first fundamental form is far from the identity.
TEST(SurfaceGeometry, PrincipalCurvaturesAreTheExtremeNormalCurvatures) {
  std::mt19937 engine(17);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    // S(u, v) = (a u + b v, c v, f(u, v)) with f a random quadratic plus cubic terms.
    const double a = 1.0 + 0.5 * uniform(engine), b = 0.6 * uniform(engine),
                 c = 0.8 + 0.3 * uniform(engine);
    const Eigen::Vector3d fz(uniform(engine), uniform(engine), uniform(engine));  // fu fv f
    SurfaceDerivatives d;
    d.point = Eigen::Vector3d(uniform(engine), uniform(engine), fz.z());
    d.du = Eigen::Vector3d(a, 0.0, fz.x());
    d.dv = Eigen::Vector3d(b, c, fz.y());
    d.duu = Eigen::Vector3d(0.0, 0.0, 2.0 * uniform(engine));
    d.duv = Eigen::Vector3d(0.0, 0.0, 2.0 * uniform(engine));
    d.dvv = Eigen::Vector3d(0.0, 0.0, 2.0 * uniform(engine));
    const SurfaceFrame frame = surfaceFrame(d);
    ASSERT_TRUE(frame.regular);
    const Eigen::Vector3d n = d.du.cross(d.dv).normalized();
    // Brute force: the curvature -II(w)/I(w) over directions (cos t, sin t) of the parameter plane.
    double best = -1e300, worst = 1e300;
    Eigen::Vector3d bestDirection = Eigen::Vector3d::Zero();
    for (int i = 0; i < 20000; ++i) {
      const double t = kPi * i / 20000;
      const double du = std::cos(t), dv = std::sin(t);
      const Eigen::Vector3d w = du * d.du + dv * d.dv;
      const double second = (du * du * d.duu + 2 * du * dv * d.duv + dv * dv * d.dvv).dot(n);
      const double k = -second / w.squaredNorm();
      if (k > best) best = k, bestDirection = w.normalized();
      worst = std::min(worst, k);
    }
    const double scale = std::max(std::abs(best), std::abs(worst));
    EXPECT_NEAR(frame.k1, best, 1e-7 * scale);
    EXPECT_NEAR(frame.k2, worst, 1e-7 * scale);
    if (best - worst > 0.1 * scale) {
      EXPECT_NEAR(std::abs(frame.e1.dot(bestDirection)), 1.0, 1e-6);
    }
    EXPECT_NEAR(frame.e1.dot(frame.e2), 0.0, 1e-14);
    EXPECT_NEAR(frame.e1.cross(frame.e2).dot(frame.normal), 1.0, 1e-14);
    EXPECT_NEAR(frame.e1.dot(frame.normal), 0.0, 1e-14);
    // Gaussian curvature of the graph form: K = det(II) / det(I).
    const double e = d.du.dot(d.du), f = d.du.dot(d.dv), g = d.dv.dot(d.dv);
    const double l = d.duu.dot(n), m = d.duv.dot(n), nn = d.dvv.dot(n);
    EXPECT_NEAR(frame.k1 * frame.k2, (l * nn - m * m) / (e * g - f * f), 1e-12 * scale * scale);
  }
}

TEST(SurfaceGeometry, DegenerateParametrizationIsReportedNotInvented) {
  SurfaceDerivatives d = sphere(1.0, 0.2, kPi / 2);  // the pole: Su = 0
  const SurfaceFrame frame = surfaceFrame(d);
  EXPECT_FALSE(frame.regular);
  EXPECT_EQ(frame.k1, 0.0);
  EXPECT_TRUE(frame.normal.allFinite());
  EXPECT_NEAR(frame.normal.norm(), 1.0, 1e-15);
  d.du = Eigen::Vector3d(1, 0, 0);
  d.dv = Eigen::Vector3d(2, 0, 0);  // parallel
  EXPECT_FALSE(surfaceFrame(d).regular);
}

}  // namespace
}  // namespace d2vdb
