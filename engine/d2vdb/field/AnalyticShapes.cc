#include "d2vdb/field/AnalyticShapes.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb {
namespace {

// Messages show shapes with 9 significant digits.
constexpr int kShapeDigits = 9;

void requireFinitePoint(const Eigen::Vector3d& p, const char* shape, const char* what) {
  if (!p.allFinite()) {
    throw InputError(std::string(shape) + ": the " + what + " " + formatPoint(p, kShapeDigits) +
                     " is not finite; give finite coordinates");
  }
}

void requirePositive(double value, const char* shape, const char* what) {
  if (!std::isfinite(value) || !(value > 0.0)) {
    throw InputError(std::string(shape) + ": the " + what +
                     " must be a finite positive number, got " + formatNumber(value, kShapeDigits));
  }
}

// A deterministic unit vector perpendicular to the unit vector `n`.
Eigen::Vector3d perpendicularUnit(const Eigen::Vector3d& n) {
  Eigen::Index leastAligned = 0;
  n.cwiseAbs().minCoeff(&leastAligned);
  const Eigen::Vector3d axis = Eigen::Vector3d::Unit(leastAligned);
  return n.cross(axis).normalized();
}

}  // namespace

// ---------------------------------------------------------------------------------------- Sphere

Sphere::Sphere(const Eigen::Vector3d& center, double radius) : center_(center), radius_(radius) {
  requireFinitePoint(center, "sphere", "centre");
  requirePositive(radius, "sphere", "radius");
}

double Sphere::signedDistance(const Eigen::Vector3d& point) const {
  return (point - center_).norm() - radius_;
}

Eigen::AlignedBox3d Sphere::bounds() const {
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(radius_);
  return Eigen::AlignedBox3d(center_ - half, center_ + half);
}

double Sphere::surfaceArea() const {
  return 4.0 * kPi * radius_ * radius_;
}

std::string Sphere::describe() const {
  return "sphere(centre " + formatPoint(center_, kShapeDigits) + ", radius " +
         formatNumber(radius_, kShapeDigits) + ")";
}

SurfacePoint Sphere::closestSurfacePoint(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d offset = point - center_;
  const double distanceToCenter = offset.norm();
  SurfacePoint result;
  result.normal = distanceToCenter > 0.0 ? Eigen::Vector3d(offset / distanceToCenter)
                                         : Eigen::Vector3d::UnitZ();
  result.point = center_ + radius_ * result.normal;
  result.e1 = perpendicularUnit(result.normal);
  result.e2 = result.normal.cross(result.e1);
  result.k1 = 1.0 / radius_;
  result.k2 = 1.0 / radius_;
  result.signedDistance = distanceToCenter - radius_;
  return result;
}

// ------------------------------------------------------------------------------------------- Box

Box::Box(const Eigen::Vector3d& min, const Eigen::Vector3d& max) : min_(min), max_(max) {
  requireFinitePoint(min, "box", "minimum corner");
  requireFinitePoint(max, "box", "maximum corner");
  if (!(min.array() < max.array()).all()) {
    throw InputError("box: the minimum corner " + formatPoint(min, kShapeDigits) +
                     " must be below the maximum corner " + formatPoint(max, kShapeDigits) +
                     " in every coordinate");
  }
}

double Box::signedDistance(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d center = 0.5 * (min_ + max_);
  const Eigen::Vector3d halfExtent = 0.5 * (max_ - min_);
  // Per-axis distance beyond the faces (negative inside the slab of that axis).
  const Eigen::Vector3d beyond = (point - center).cwiseAbs() - halfExtent;
  const double outside = beyond.cwiseMax(0.0).norm();
  const double inside = std::min(beyond.maxCoeff(), 0.0);
  return outside + inside;
}

Eigen::AlignedBox3d Box::bounds() const {
  return Eigen::AlignedBox3d(min_, max_);
}

double Box::surfaceArea() const {
  const Eigen::Vector3d e = max_ - min_;
  return 2.0 * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
}

std::string Box::describe() const {
  return "box(min " + formatPoint(min_, kShapeDigits) + ", max " + formatPoint(max_, kShapeDigits) +
         ")";
}

// ----------------------------------------------------------------------------------------- Torus

Torus::Torus(const Eigen::Vector3d& center, double majorRadius, double minorRadius)
    : center_(center), majorRadius_(majorRadius), minorRadius_(minorRadius) {
  requireFinitePoint(center, "torus", "centre");
  requirePositive(majorRadius, "torus", "major radius");
  requirePositive(minorRadius, "torus", "minor radius");
  if (!(minorRadius < majorRadius)) {
    throw InputError("torus: the minor radius " + formatNumber(minorRadius, kShapeDigits) +
                     " must be smaller than the major radius " +
                     formatNumber(majorRadius, kShapeDigits) + " (only ring tori are supported)");
  }
}

double Torus::signedDistance(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d offset = point - center_;
  const double radial = std::hypot(offset.x(), offset.y());
  return std::hypot(radial - majorRadius_, offset.z()) - minorRadius_;
}

Eigen::AlignedBox3d Torus::bounds() const {
  const double outer = majorRadius_ + minorRadius_;
  const Eigen::Vector3d half(outer, outer, minorRadius_);
  return Eigen::AlignedBox3d(center_ - half, center_ + half);
}

double Torus::surfaceArea() const {
  return 4.0 * kPi * kPi * majorRadius_ * minorRadius_;
}

std::string Torus::describe() const {
  return "torus(centre " + formatPoint(center_, kShapeDigits) + ", major radius " +
         formatNumber(majorRadius_, kShapeDigits) + ", minor radius " +
         formatNumber(minorRadius_, kShapeDigits) + ", axis +z)";
}

SurfacePoint Torus::closestSurfacePoint(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d offset = point - center_;
  const double radial = std::hypot(offset.x(), offset.y());
  // Unit vector from the axis towards the point, in the equatorial plane.
  const Eigen::Vector3d outward =
      radial > 0.0 ? Eigen::Vector3d(offset.x() / radial, offset.y() / radial, 0.0)
                   : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d corePoint = center_ + majorRadius_ * outward;
  const Eigen::Vector3d fromCore = point - corePoint;
  const double distanceToCore = fromCore.norm();

  SurfacePoint result;
  result.normal =
      distanceToCore > 0.0 ? Eigen::Vector3d(fromCore / distanceToCore) : Eigen::Vector3d::UnitZ();
  result.point = corePoint + minorRadius_ * result.normal;
  const double cosPhi = result.normal.dot(outward);
  result.e2 = Eigen::Vector3d::UnitZ().cross(outward);  // around the z axis
  result.e1 = result.e2.cross(result.normal);           // around the tube; e1 x e2 = normal
  result.k1 = 1.0 / minorRadius_;
  result.k2 = cosPhi / (majorRadius_ + minorRadius_ * cosPhi);
  result.signedDistance = distanceToCore - minorRadius_;
  return result;
}

// -------------------------------------------------------------------------------- CappedCylinder

CappedCylinder::CappedCylinder(const Eigen::Vector3d& center, double radius, double height)
    : center_(center), radius_(radius), height_(height) {
  requireFinitePoint(center, "capped cylinder", "centre");
  requirePositive(radius, "capped cylinder", "radius");
  requirePositive(height, "capped cylinder", "height");
}

double CappedCylinder::signedDistance(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d offset = point - center_;
  const double beyondSide = std::hypot(offset.x(), offset.y()) - radius_;
  const double beyondCap = std::abs(offset.z()) - 0.5 * height_;
  const double outside = std::hypot(std::max(beyondSide, 0.0), std::max(beyondCap, 0.0));
  const double inside = std::min(std::max(beyondSide, beyondCap), 0.0);
  return outside + inside;
}

Eigen::AlignedBox3d CappedCylinder::bounds() const {
  const Eigen::Vector3d half(radius_, radius_, 0.5 * height_);
  return Eigen::AlignedBox3d(center_ - half, center_ + half);
}

double CappedCylinder::surfaceArea() const {
  return 2.0 * kPi * radius_ * height_ + 2.0 * kPi * radius_ * radius_;
}

std::string CappedCylinder::describe() const {
  return "capped cylinder(centre " + formatPoint(center_, kShapeDigits) + ", radius " +
         formatNumber(radius_, kShapeDigits) + ", height " + formatNumber(height_, kShapeDigits) +
         ", axis +z)";
}

}  // namespace d2vdb
