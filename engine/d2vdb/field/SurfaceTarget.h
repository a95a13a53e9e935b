// Exact squared-distance approximants of a B-spline surface, computed from the surface itself by
// point-surface projection: a fitting target for surfaces (and curves) that need no grid.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

#include "d2vdb/field/SquaredDistanceTarget.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

class SurfaceProjector;
struct SurfaceFrame;  // d2vdb/spline/SurfaceGeometry.h

/// The approximant of the squared distance from `point` to a surface at a footpoint with frame
/// `frame` (surfaceFrame()), as SurfaceTarget describes it: kind Surface, the frame's normal,
/// tangent e1 and curvatures, signed distance (point - footpoint) . normal; a point distance
/// (kFlagEndPoint, normal toward `point`) when `onBoundary` (the footpoint lies on the boundary of
/// an open direction) or the frame is not regular. Used by SurfaceTarget and by the surface
/// fitters (surfaceApproximantAt(), SurfaceFitter.h).
Approximant surfaceApproximantFromFrame(const SurfaceFrame& frame, bool onBoundary,
                                        const Eigen::Vector3d& point);

/// Exact approximants of a tensor-product B-spline surface (TargetKind::Surface), answered
/// anywhere in its domain.
///
/// The footpoint s is the nearest surface point (SurfaceProjector::nearest); the frame and the
/// principal curvatures are the surface's own there (surfaceFrame()): normal along Su x Sv,
/// tangent = e1, k1 >= k2 positive where the surface bends away from the normal, signed distance
/// (x - s) . normal. A closed surface whose Su x Sv points inward answers with inward normals and
/// the opposite signs of distance and curvatures, which leaves every quadratic form unchanged.
/// Where the footpoint lies on the boundary of an open direction the distance is to an edge, not
/// along the normal: the approximant gets kFlagEndPoint (its SDM and TDM forms are the PDM form),
/// normal = the unit vector toward the query point, distance = |x - s|. Where the surface is not
/// regular (Su x Sv = 0) the approximant is likewise a point distance (kFlagEndPoint).
///
/// The domain is the control points' bounding box padded by `domainPadding` times its largest
/// side on every side. resolvedLength() is 0 (exact). Immutable; thread-safe.
class SurfaceTarget final : public SquaredDistanceTarget {
 public:
  /// Target from a surface (its own copy). Throws InputError when all control points coincide or
  /// the padding is negative or not finite.
  explicit SurfaceTarget(const BSplineSurface& surface, double domainPadding = 0.5);
  ~SurfaceTarget() override;
  SurfaceTarget(SurfaceTarget&&) noexcept;
  SurfaceTarget& operator=(SurfaceTarget&&) noexcept;

  TargetKind kind() const override { return TargetKind::Surface; }
  Eigen::AlignedBox3d domain() const override { return domain_; }
  Approximant approximantAt(const Eigen::Vector3d& point) const override;
  std::string describe() const override;

  /// The approximant at `point` without the domain check. InputError when `point` is not finite.
  Approximant approximantAtAnyPoint(const Eigen::Vector3d& point) const;

  /// The target surface.
  const BSplineSurface& surface() const;
  /// Bounding box of its control points (contains the surface).
  const Eigen::AlignedBox3d& surfaceBounds() const { return surfaceBounds_; }
  /// samplesU x samplesV points of the surface on a uniform parameter grid (both ends included),
  /// for placing initial surfaces. InputError for fewer than 2 samples in a direction.
  std::vector<Eigen::Vector3d> samplePoints(int samplesU, int samplesV) const;
  /// Optional label for describe() (e.g. the file name).
  void setLabel(std::string label) { label_ = std::move(label); }

 private:
  std::unique_ptr<SurfaceProjector> projector_;
  Eigen::AlignedBox3d surfaceBounds_;
  Eigen::AlignedBox3d domain_;
  std::string label_;
};

}  // namespace d2vdb
