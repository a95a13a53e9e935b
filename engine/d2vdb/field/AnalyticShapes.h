// Analytic solids with exact signed distance functions: the references every distance-field test
// compares against, and sources of primitive level sets (Primitives.h). OpenVDB-free.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>

namespace d2vdb {

/// The closest surface point of a smooth analytic shape and the differential geometry there.
/// Conventions (engine/README.md, "Conventions"): `normal` is the outward unit normal; principal
/// curvatures are positive where the surface bends away from the normal (a sphere of radius R has
/// k1 = k2 = 1/R); e1, e2 are unit principal directions with e1 x e2 = normal; curvatures in
/// 1/world units.
struct SurfacePoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< closest point on the surface (world)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< outward unit normal at `point`
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();      ///< principal direction of k1
  Eigen::Vector3d e2 = Eigen::Vector3d::UnitY();      ///< principal direction of k2
  double k1 = 0.0;                                    ///< principal curvature along e1
  double k2 = 0.0;                                    ///< principal curvature along e2
  double signedDistance = 0.0;  ///< signed distance from the query point (negative inside)
};

/// A closed solid with an exact signed distance function, negative inside, in world units.
/// Exact means 1-Lipschitz and equal to the Euclidean distance to the boundary, so a bound on
/// |d| at one point bounds it in a whole neighbourhood (Primitives.h relies on this).
class AnalyticShape {
 public:
  virtual ~AnalyticShape() = default;

  /// Exact signed distance from `point` to the surface (world units, d < 0 inside).
  virtual double signedDistance(const Eigen::Vector3d& point) const = 0;

  /// Tight axis-aligned bounding box of the solid (world units).
  virtual Eigen::AlignedBox3d bounds() const = 0;

  /// Exact surface area (world units squared); used for voxel-budget estimates.
  virtual double surfaceArea() const = 0;

  /// Short human-readable description with parameters, e.g. "sphere(centre (0,0,0), radius 1)".
  virtual std::string describe() const = 0;
};

/// Sphere of radius `radius` about `center`.
/// Throws InputError unless the centre is finite and the radius finite and positive.
class Sphere final : public AnalyticShape {
 public:
  Sphere(const Eigen::Vector3d& center, double radius);

  double signedDistance(const Eigen::Vector3d& point) const override;
  Eigen::AlignedBox3d bounds() const override;
  double surfaceArea() const override;
  std::string describe() const override;

  /// Closest point, outward normal and curvatures k1 = k2 = 1/radius (an umbilic surface: e1, e2
  /// are any orthonormal tangent pair, chosen deterministically). At the centre itself every
  /// surface point is closest; the point in direction +z is returned.
  SurfacePoint closestSurfacePoint(const Eigen::Vector3d& point) const;

  const Eigen::Vector3d& center() const { return center_; }
  double radius() const { return radius_; }

 private:
  Eigen::Vector3d center_;
  double radius_;
};

/// Axis-aligned box [min, max] (solid, sharp edges and corners).
/// Throws InputError unless both corners are finite and min < max in every coordinate.
class Box final : public AnalyticShape {
 public:
  Box(const Eigen::Vector3d& min, const Eigen::Vector3d& max);

  double signedDistance(const Eigen::Vector3d& point) const override;
  Eigen::AlignedBox3d bounds() const override;
  double surfaceArea() const override;
  std::string describe() const override;

  const Eigen::Vector3d& min() const { return min_; }
  const Eigen::Vector3d& max() const { return max_; }

 private:
  Eigen::Vector3d min_;
  Eigen::Vector3d max_;
};

/// Ring torus about the axis through `center` parallel to +z: the set of points at distance
/// `minorRadius` from the circle of radius `majorRadius` about `center` in the plane z = center.z.
/// Throws InputError unless parameters are finite and 0 < minorRadius < majorRadius.
class Torus final : public AnalyticShape {
 public:
  Torus(const Eigen::Vector3d& center, double majorRadius, double minorRadius);

  double signedDistance(const Eigen::Vector3d& point) const override;
  Eigen::AlignedBox3d bounds() const override;
  double surfaceArea() const override;
  std::string describe() const override;

  /// Closest point and differential geometry. With phi the angle around the tube (phi = 0 on the
  /// outer equator), e1 runs around the tube with k1 = 1/minorRadius and e2 around the z axis with
  /// k2 = cos(phi) / (majorRadius + minorRadius cos(phi)) (negative on the inner, saddle-shaped
  /// half). On the cut locus (the z axis, or the core circle itself) the closest point is not
  /// unique; the one in the direction of +x, respectively of +z, is returned.
  SurfacePoint closestSurfacePoint(const Eigen::Vector3d& point) const;

  const Eigen::Vector3d& center() const { return center_; }
  double majorRadius() const { return majorRadius_; }
  double minorRadius() const { return minorRadius_; }

 private:
  Eigen::Vector3d center_;
  double majorRadius_;
  double minorRadius_;
};

/// Solid circular cylinder with flat caps, axis parallel to +z through `center`, which is the
/// midpoint of the axis: it spans z in [center.z - height/2, center.z + height/2].
/// Throws InputError unless parameters are finite and radius, height > 0.
class CappedCylinder final : public AnalyticShape {
 public:
  CappedCylinder(const Eigen::Vector3d& center, double radius, double height);

  double signedDistance(const Eigen::Vector3d& point) const override;
  Eigen::AlignedBox3d bounds() const override;
  double surfaceArea() const override;
  std::string describe() const override;

  const Eigen::Vector3d& center() const { return center_; }
  double radius() const { return radius_; }
  double height() const { return height_; }

 private:
  Eigen::Vector3d center_;
  double radius_;
  double height_;
};

}  // namespace d2vdb
