// Exact squared-distance targets of analytic surfaces for the surface-fitting tests (independent
// of the approximant field): torus, infinite cylinder and the one-sheeted hyperboloid
// x^2 + y^2 - z^2 = 1; and reference distances to them.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/ExactApproximant.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/SquaredDistanceTarget.h"

namespace d2vdb::test {

/// The exact torus (AnalyticShapes' Torus::closestSurfacePoint) as a fitting target.
class ExactTorusTarget final : public SquaredDistanceTarget {
 public:
  ExactTorusTarget(double major, double minor) : torus_(Eigen::Vector3d::Zero(), major, minor) {}
  TargetKind kind() const override { return TargetKind::Surface; }
  Eigen::AlignedBox3d domain() const override {
    const double r = torus_.majorRadius() + 3 * torus_.minorRadius();
    return Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-r), Eigen::Vector3d::Constant(r));
  }
  Approximant approximantAt(const Eigen::Vector3d& point) const override {
    return approximantFrom(torus_.closestSurfacePoint(point), point);
  }
  std::string describe() const override { return "exact torus"; }
  /// Exact distance to the torus.
  double distance(const Eigen::Vector3d& p) const { return std::abs(torus_.signedDistance(p)); }

 private:
  Torus torus_;
};

/// The infinite circular cylinder x^2 + y^2 = R^2 (axis z) as an exact target; e1 runs around
/// the axis (k1 = 1/R), e2 along it (k2 = 0).
class ExactCylinderTarget final : public SquaredDistanceTarget {
 public:
  explicit ExactCylinderTarget(double radius, double halfHeight = 4.0)
      : radius_(radius), halfHeight_(halfHeight) {}
  TargetKind kind() const override { return TargetKind::Surface; }
  Eigen::AlignedBox3d domain() const override {
    const double r = 3 * radius_;
    return Eigen::AlignedBox3d(Eigen::Vector3d(-r, -r, -halfHeight_),
                               Eigen::Vector3d(r, r, halfHeight_));
  }
  Approximant approximantAt(const Eigen::Vector3d& point) const override {
    const Eigen::Vector2d radial = point.head<2>();
    const double rho = radial.norm();
    const Eigen::Vector2d direction =
        rho > 0 ? Eigen::Vector2d(radial / rho) : Eigen::Vector2d(1, 0);
    SurfacePoint s;
    s.point = Eigen::Vector3d(radius_ * direction.x(), radius_ * direction.y(), point.z());
    s.normal = Eigen::Vector3d(direction.x(), direction.y(), 0.0);
    s.e1 = Eigen::Vector3d(-direction.y(), direction.x(), 0.0);
    s.e2 = s.normal.cross(s.e1);
    s.k1 = 1.0 / radius_;
    s.k2 = 0.0;
    s.signedDistance = rho - radius_;
    return approximantFrom(s, point);
  }
  std::string describe() const override { return "exact cylinder"; }
  double distance(const Eigen::Vector3d& p) const { return std::abs(p.head<2>().norm() - radius_); }

 private:
  double radius_;
  double halfHeight_;
};

/// The one-sheeted hyperboloid x^2 + y^2 - z^2 = 1 for |z| <= zMax, as an exact target: the
/// closest point in the meridian half-plane of the query, (rho, z) on rho^2 - z^2 = 1, by Newton on
/// the parametrisation (cosh t, sinh t) from the best of a dense search, clamped to the patch
/// (a clamped footpoint lies on a rim circle: a point distance, kFlagEndPoint); normal outward from
/// the axis (grad of x^2 + y^2 - z^2), curvatures of the surface of revolution there.
class ExactHyperboloidTarget final : public SquaredDistanceTarget {
 public:
  explicit ExactHyperboloidTarget(double zMax = 1.0) : tMax_(std::asinh(zMax)) {}
  TargetKind kind() const override { return TargetKind::Surface; }
  Eigen::AlignedBox3d domain() const override {
    return Eigen::AlignedBox3d(Eigen::Vector3d(-4, -4, -3), Eigen::Vector3d(4, 4, 3));
  }
  /// Parameter t of the meridian point (cosh t, sinh t) nearest to (rho, z).
  static double nearestMeridianParameter(double rho, double z) {
    double best = 0.0, bestValue = 1e300;
    for (int i = -400; i <= 400; ++i) {
      const double t = 0.0075 * i;
      const double value = std::pow(std::cosh(t) - rho, 2) + std::pow(std::sinh(t) - z, 2);
      if (value < bestValue) bestValue = value, best = t;
    }
    double t = best;
    for (int iteration = 0; iteration < 50; ++iteration) {
      // f(t) = (cosh t - rho) sinh t + (sinh t - z) cosh t; f' = cosh(2t) ... by hand:
      const double c = std::cosh(t), s = std::sinh(t);
      const double f = (c - rho) * s + (s - z) * c;
      const double df = s * s + (c - rho) * c + c * c + (s - z) * s;
      if (!(df > 0)) break;
      const double step = f / df;
      t -= step;
      if (std::abs(step) < 1e-16) break;
    }
    return t;
  }
  Approximant approximantAt(const Eigen::Vector3d& point) const override {
    const double rho = point.head<2>().norm();
    const Eigen::Vector2d direction =
        rho > 0 ? Eigen::Vector2d(point.head<2>() / rho) : Eigen::Vector2d(1, 0);
    const double unclamped = nearestMeridianParameter(rho, point.z());
    const double t = std::clamp(unclamped, -tMax_, tMax_);
    const double c = std::cosh(t), s = std::sinh(t);
    if (t != unclamped) {  // the rim: a point distance
      Approximant a;
      a.kind = TargetKind::Surface;
      a.origin = point;
      a.footpoint = Eigen::Vector3d(c * direction.x(), c * direction.y(), s);
      a.flags |= kFlagEndPoint;
      a.distance = (point - a.footpoint).norm();
      a.normal = a.distance > 0 ? Eigen::Vector3d((point - a.footpoint) / a.distance)
                                : Eigen::Vector3d::UnitZ();
      a.tangent = a.normal.unitOrthogonal();
      return a;
    }
    SurfacePoint sp;
    sp.point = Eigen::Vector3d(c * direction.x(), c * direction.y(), s);
    // Meridian tangent (s, c) in (rho, z); outward normal (c, -s) / |.|.
    const double length = std::hypot(c, s);
    const Eigen::Vector2d normal2(c / length, -s / length);
    sp.normal =
        Eigen::Vector3d(normal2.x() * direction.x(), normal2.x() * direction.y(), normal2.y());
    // Parallel circle: normal curvature 1/rho projected: k = normal_rho / rho = c / (length c).
    const double kParallel = normal2.x() / c;
    // Meridian curve (cosh t, sinh t): curvature (x' y'' - y' x'') / (x'^2 + y'^2)^(3/2) with
    // x = cosh, y = sinh: (s s - c c) / length^3 = -1 / length^3; it bends toward +rho side away
    // from the outward normal? The meridian hyperbola bends away from the axis: k < 0.
    const double kMeridian = -1.0 / (length * length * length);
    const Eigen::Vector3d parallelDirection(-direction.y(), direction.x(), 0.0);
    const Eigen::Vector3d meridianDirection =
        Eigen::Vector3d(s * direction.x(), s * direction.y(), c) / length;
    if (kParallel >= kMeridian) {
      sp.k1 = kParallel, sp.k2 = kMeridian;
      sp.e1 = parallelDirection;
    } else {
      sp.k1 = kMeridian, sp.k2 = kParallel;
      sp.e1 = meridianDirection;
    }
    sp.e2 = sp.normal.cross(sp.e1);
    sp.signedDistance = (point - sp.point).dot(sp.normal);
    return approximantFrom(sp, point);
  }
  std::string describe() const override { return "exact hyperboloid"; }
  /// Exact distance to the patch |z| <= zMax.
  double distance(const Eigen::Vector3d& p) const {
    const double rho = p.head<2>().norm();
    const double t = std::clamp(nearestMeridianParameter(rho, p.z()), -tMax_, tMax_);
    return std::hypot(std::cosh(t) - rho, std::sinh(t) - p.z());
  }

 private:
  double tMax_;
};

}  // namespace d2vdb::test
