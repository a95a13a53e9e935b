// Analytic shapes: hand-computed distances, brute-force distances to densely sampled surfaces,
// and curvatures checked against a finite-difference Hessian of the distance (engine/README.md,
// "Conventions").
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/field/AnalyticShapes.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

// Distance from `p` to the nearest of `samples`.
double nearestSampleDistance(const std::vector<Eigen::Vector3d>& samples,
                             const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& s : samples) best = std::min(best, (s - p).squaredNorm());
  return std::sqrt(best);
}

// For random points in `region`, |d| must match the distance to the sampled surface within the
// sampling step (samples lie on the surface: never closer than |d|, and within `spacing`
// of the true closest point), and the sign must match the independent containment test.
void expectMatchesSampledSurface(const AnalyticShape& shape,
                                 const std::vector<Eigen::Vector3d>& samples, double spacing,
                                 const std::function<bool(const Eigen::Vector3d&)>& inside,
                                 const Eigen::AlignedBox3d& region) {
  std::mt19937 random(12345);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 60; ++i) {
    const Eigen::Vector3d p =
        region.min() +
        Eigen::Vector3d(unit(random), unit(random), unit(random)).cwiseProduct(region.sizes());
    const double d = shape.signedDistance(p);
    const double sampled = nearestSampleDistance(samples, p);
    EXPECT_GE(sampled, std::abs(d) - 1e-12) << shape.describe() << " at " << p.transpose();
    EXPECT_LE(sampled, std::abs(d) + spacing) << shape.describe() << " at " << p.transpose();
    if (std::abs(d) > 1e-9) {
      EXPECT_EQ(d < 0.0, inside(p)) << shape.describe() << " at " << p.transpose();
    }
  }
}

// Central-difference Hessian of the signed distance.
Eigen::Matrix3d distanceHessian(const AnalyticShape& shape, const Eigen::Vector3d& p, double h) {
  Eigen::Matrix3d hessian;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector3d ei = h * Eigen::Vector3d::Unit(i);
      const Eigen::Vector3d ej = h * Eigen::Vector3d::Unit(j);
      hessian(i, j) = (shape.signedDistance(p + ei + ej) - shape.signedDistance(p + ei - ej) -
                       shape.signedDistance(p - ei + ej) + shape.signedDistance(p - ei - ej)) /
                      (4.0 * h * h);
    }
  }
  return hessian;
}

// Hessian(d)(p) = sum_i k_i / (1 + d k_i) e_i e_i^T (engine/README.md), checked against finite
// differences; also the frame and footpoint of the SurfacePoint.
void expectConsistentSurfacePoint(const AnalyticShape& shape, const SurfacePoint& s,
                                  const Eigen::Vector3d& p) {
  const double d = shape.signedDistance(p);
  EXPECT_NEAR(s.signedDistance, d, 1e-12);
  EXPECT_NEAR((p - s.point).norm(), std::abs(d), 1e-12);
  EXPECT_NEAR(shape.signedDistance(s.point), 0.0, 1e-12);
  EXPECT_TRUE((p - (s.point + d * s.normal)).isZero(1e-12));
  EXPECT_NEAR(s.normal.norm(), 1.0, 1e-12);
  EXPECT_NEAR(s.e1.norm(), 1.0, 1e-12);
  EXPECT_NEAR(s.e2.norm(), 1.0, 1e-12);
  EXPECT_TRUE(s.e1.cross(s.e2).isApprox(s.normal, 1e-12));
  const Eigen::Matrix3d expected = s.k1 / (1.0 + d * s.k1) * s.e1 * s.e1.transpose() +
                                   s.k2 / (1.0 + d * s.k2) * s.e2 * s.e2.transpose();
  const Eigen::Matrix3d numeric = distanceHessian(shape, p, 1e-4);
  EXPECT_TRUE((numeric - expected).cwiseAbs().maxCoeff() < 1e-5) << "numeric Hessian\n"
                                                                 << numeric << "\nexpected\n"
                                                                 << expected;
}

TEST(AnalyticShapes, SphereDistancesByHand) {
  const Sphere sphere({1, 2, 3}, 2.0);
  EXPECT_DOUBLE_EQ(sphere.signedDistance({1, 2, 3}), -2.0);
  EXPECT_DOUBLE_EQ(sphere.signedDistance({1, 2, 6}), 1.0);
  EXPECT_DOUBLE_EQ(sphere.signedDistance({1, 2 + 0.5, 3}), -1.5);
  EXPECT_NEAR(sphere.signedDistance({4, 6, 3}), 3.0, 1e-15);  // 3-4-5 triangle
  EXPECT_DOUBLE_EQ(sphere.surfaceArea(), 16.0 * kPi);
  EXPECT_TRUE(sphere.bounds().min().isApprox(Eigen::Vector3d(-1, 0, 1)));
  EXPECT_TRUE(sphere.bounds().max().isApprox(Eigen::Vector3d(3, 4, 5)));
}

TEST(AnalyticShapes, SphereCurvatureIsInverseRadiusWithOutwardNormal) {
  const Sphere sphere({0.5, -1, 0}, 2.0);
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(3, 0.5, 1), Eigen::Vector3d(0.9, -0.7, 0.4), Eigen::Vector3d(-2, -1, 0)}) {
    const SurfacePoint s = sphere.closestSurfacePoint(p);
    EXPECT_DOUBLE_EQ(s.k1, 0.5);
    EXPECT_DOUBLE_EQ(s.k2, 0.5);
    EXPECT_TRUE(s.normal.isApprox((p - sphere.center()).normalized(), 1e-14));
    expectConsistentSurfacePoint(sphere, s, p);
  }
  // The centre is on the cut locus: documented choice +z.
  const SurfacePoint atCenter = sphere.closestSurfacePoint(sphere.center());
  EXPECT_TRUE(atCenter.normal.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_DOUBLE_EQ(atCenter.signedDistance, -2.0);
}

TEST(AnalyticShapes, BoxDistancesByHand) {
  const Box box({0, 0, 0}, {1, 2, 3});
  EXPECT_DOUBLE_EQ(box.signedDistance({0.5, 1, 1.5}), -0.5);      // centre: nearest faces x = 0, 1
  EXPECT_DOUBLE_EQ(box.signedDistance({0.2, 1, 1.5}), -0.2);      // near face x = 0
  EXPECT_NEAR(box.signedDistance({0.5, 1.9, 1.5}), -0.1, 1e-15);  // near face y = 2
  EXPECT_DOUBLE_EQ(box.signedDistance({2, 1, 1.5}), 1.0);         // beyond face x = 1
  EXPECT_DOUBLE_EQ(box.signedDistance({2, 3, 1.5}), std::sqrt(2.0));  // beyond an edge
  EXPECT_DOUBLE_EQ(box.signedDistance({2, 3, 4}), std::sqrt(3.0));    // beyond a corner
  EXPECT_DOUBLE_EQ(box.signedDistance({1, 2, 3}), 0.0);               // the corner itself
  EXPECT_DOUBLE_EQ(box.surfaceArea(), 2.0 * (2 + 6 + 3));
}

TEST(AnalyticShapes, TorusDistancesByHand) {
  const Torus torus({0, 0, 0}, 2.0, 0.5);
  EXPECT_DOUBLE_EQ(torus.signedDistance({2, 0, 0}), -0.5);  // on the core circle
  EXPECT_DOUBLE_EQ(torus.signedDistance({0, 3, 0}), 0.5);
  EXPECT_DOUBLE_EQ(torus.signedDistance({0, 0, 0}), 1.5);  // centre of the hole
  EXPECT_DOUBLE_EQ(torus.signedDistance({0, 0, 1}), std::sqrt(5.0) - 0.5);
  EXPECT_DOUBLE_EQ(torus.signedDistance({-2, 0, 0.25}), -0.25);
  EXPECT_DOUBLE_EQ(torus.surfaceArea(), 4.0 * kPi * kPi * 2.0 * 0.5);
  EXPECT_TRUE(torus.bounds().max().isApprox(Eigen::Vector3d(2.5, 2.5, 0.5)));
}

TEST(AnalyticShapes, TorusCurvatures) {
  const Torus torus({1, -1, 0.5}, 2.0, 0.5);
  const Eigen::Vector3d c = torus.center();
  // Outer equator: both curvatures convex, 1/r and 1/(R + r).
  SurfacePoint s = torus.closestSurfacePoint(c + Eigen::Vector3d(3.2, 0, 0));
  EXPECT_DOUBLE_EQ(s.k1, 2.0);
  EXPECT_DOUBLE_EQ(s.k2, 1.0 / 2.5);
  EXPECT_TRUE(s.normal.isApprox(Eigen::Vector3d::UnitX()));
  // Inner equator: saddle, k2 = -1/(R - r).
  s = torus.closestSurfacePoint(c + Eigen::Vector3d(0, 1.2, 0));
  EXPECT_DOUBLE_EQ(s.k1, 2.0);
  EXPECT_DOUBLE_EQ(s.k2, -1.0 / 1.5);
  EXPECT_TRUE(s.normal.isApprox(-Eigen::Vector3d::UnitY()));
  // Top circle: the normal is vertical, k2 = 0.
  s = torus.closestSurfacePoint(c + Eigen::Vector3d(0, -2, 0.9));
  EXPECT_NEAR(s.k2, 0.0, 1e-15);
  EXPECT_TRUE(s.normal.isApprox(Eigen::Vector3d::UnitZ()));
  // General points, inside and outside the tube, against the finite-difference Hessian.
  for (const Eigen::Vector3d& offset :
       {Eigen::Vector3d(1.1, 1.3, 0.2), Eigen::Vector3d(-2.2, 0.3, -0.35),
        Eigen::Vector3d(0.4, -1.45, 0.1), Eigen::Vector3d(1.9, 0.4, 0.7)}) {
    const Eigen::Vector3d p = c + offset;
    expectConsistentSurfacePoint(torus, torus.closestSurfacePoint(p), p);
  }
}

TEST(AnalyticShapes, CappedCylinderDistancesByHand) {
  const CappedCylinder cylinder({0, 0, 0}, 1.0, 2.0);
  EXPECT_DOUBLE_EQ(cylinder.signedDistance({0, 0, 0}), -1.0);
  EXPECT_DOUBLE_EQ(cylinder.signedDistance({0, 0, 0.75}), -0.25);  // nearest the top cap
  EXPECT_DOUBLE_EQ(cylinder.signedDistance({0.9, 0, 0}), -0.1);    // nearest the side
  EXPECT_DOUBLE_EQ(cylinder.signedDistance({0, 2, 0}), 1.0);
  EXPECT_DOUBLE_EQ(cylinder.signedDistance({0.5, 0, -3}), 2.0);
  EXPECT_DOUBLE_EQ(cylinder.signedDistance({3, 4, 0.5}), 4.0);           // beyond the side only
  EXPECT_DOUBLE_EQ(cylinder.signedDistance({0, 2, 2}), std::sqrt(2.0));  // beyond the rim
  EXPECT_DOUBLE_EQ(cylinder.surfaceArea(), 2.0 * kPi * 2.0 + 2.0 * kPi);
}

TEST(AnalyticShapes, DistancesMatchDenselySampledSurfaces) {
  const int n = 160;
  {
    const Box box({-1, -0.5, 0}, {1, 0.5, 0.8});
    std::vector<Eigen::Vector3d> samples;
    const Eigen::Vector3d lo = box.min();
    const Eigen::Vector3d hi = box.max();
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3;
      const int v = (axis + 2) % 3;
      for (const double side : {lo[axis], hi[axis]}) {
        for (int i = 0; i <= n; ++i) {
          for (int j = 0; j <= n; ++j) {
            Eigen::Vector3d p;
            p[axis] = side;
            p[u] = lo[u] + (hi[u] - lo[u]) * i / n;
            p[v] = lo[v] + (hi[v] - lo[v]) * j / n;
            samples.push_back(p);
          }
        }
      }
    }
    const double spacing = 2.0 / n;  // longest side / n, a conservative sample spacing
    expectMatchesSampledSurface(
        box, samples, spacing,
        [&](const Eigen::Vector3d& p) {
          return (p.array() > lo.array()).all() && (p.array() < hi.array()).all();
        },
        Eigen::AlignedBox3d(Eigen::Vector3d(-1.5, -1, -0.5), Eigen::Vector3d(1.5, 1, 1.3)));
  }
  {
    const Torus torus({0.2, 0.1, -0.1}, 1.0, 0.3);
    std::vector<Eigen::Vector3d> samples;
    const int around = 4 * n;
    for (int i = 0; i < around; ++i) {
      const double theta = 2.0 * kPi * i / around;
      for (int j = 0; j < n; ++j) {
        const double phi = 2.0 * kPi * j / n;
        const double radial = 1.0 + 0.3 * std::cos(phi);
        samples.push_back(torus.center() + Eigen::Vector3d(radial * std::cos(theta),
                                                           radial * std::sin(theta),
                                                           0.3 * std::sin(phi)));
      }
    }
    const double spacing = 2.0 * kPi * 1.3 / around + 2.0 * kPi * 0.3 / n;
    expectMatchesSampledSurface(
        torus, samples, spacing,
        [&](const Eigen::Vector3d& p) {
          const Eigen::Vector3d q = p - torus.center();
          return std::pow(std::hypot(q.x(), q.y()) - 1.0, 2) + q.z() * q.z() < 0.09;
        },
        Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.3, -0.6), Eigen::Vector3d(1.6, 1.5, 0.4)));
  }
  {
    const CappedCylinder cylinder({0, 0, 0.5}, 0.6, 1.0);
    std::vector<Eigen::Vector3d> samples;
    const int around = 4 * n;
    for (int i = 0; i < around; ++i) {
      const double theta = 2.0 * kPi * i / around;
      const Eigen::Vector3d radial(std::cos(theta), std::sin(theta), 0.0);
      for (int j = 0; j <= n; ++j) {
        samples.push_back(cylinder.center() + 0.6 * radial +
                          Eigen::Vector3d(0, 0, -0.5 + 1.0 * j / n));
        for (const double cap : {-0.5, 0.5}) {  // concentric rings on both caps
          samples.push_back(cylinder.center() + 0.6 * j / n * radial + Eigen::Vector3d(0, 0, cap));
        }
      }
    }
    const double spacing = 2.0 * kPi * 0.6 / around + 1.0 / n;
    expectMatchesSampledSurface(
        cylinder, samples, spacing,
        [&](const Eigen::Vector3d& p) {
          const Eigen::Vector3d q = p - cylinder.center();
          return std::hypot(q.x(), q.y()) < 0.6 && std::abs(q.z()) < 0.5;
        },
        Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -0.4), Eigen::Vector3d(1, 1, 1.4)));
  }
}

TEST(AnalyticShapes, RejectsInvalidParameters) {
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Sphere(origin, 0.0), InputError);
  EXPECT_THROW(Sphere(origin, -1.0), InputError);
  EXPECT_THROW(Sphere(origin, nan), InputError);
  EXPECT_THROW(Sphere(Eigen::Vector3d(nan, 0, 0), 1.0), InputError);
  EXPECT_THROW(Box({0, 0, 0}, {1, 0, 1}), InputError);
  EXPECT_THROW(Box({0, 0, 0}, {1, -1, 1}), InputError);
  EXPECT_THROW(Torus(origin, 1.0, 1.0), InputError);
  EXPECT_THROW(Torus(origin, 1.0, 2.0), InputError);
  EXPECT_THROW(Torus(origin, 1.0, 0.0), InputError);
  EXPECT_THROW(CappedCylinder(origin, 1.0, 0.0), InputError);
  EXPECT_THROW(CappedCylinder(origin, -1.0, 1.0), InputError);
  try {
    Torus(origin, 1.0, 1.5);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("minor radius"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace d2vdb
