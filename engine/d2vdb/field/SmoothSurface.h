// A smooth surface (parametric pseudo-manifold) as a fitting target: exact projection onto the
// surface and the surface's own curvatures at the footpoint.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <string>

#include "d2vdb/field/SquaredDistanceTarget.h"
#include "d2vdb/manifold/PseudoManifold.h"

namespace d2vdb {

namespace detail {
class NearestPointTree;
}

/// The squared-distance approximants of a closed smooth surface built from a mesh
/// (PseudoManifold.h), computed from the surface itself rather than from a grid:
/// the footpoint of a query point x is its projection onto the surface (the surface point nearest
/// to x among dense samples of every face, then Newton's method on |X - x|^2 in the coordinates of
/// the chart nearest to the iterate, walking across faces and charts), and the normal, k1 >= k2
/// and e1 at the footpoint come from the surface's first and second derivatives there. The
/// distance is signed by the outward normal (negative inside). Where 1 + d k_i < 0.05 (at or past
/// a centre of curvature, near the medial axis) the approximant carries kFlagCutLocus; where
/// the projection did not converge, kFlagDegradedEstimate (the footpoint is then the best point
/// found).
///
/// The domain is the surface's bounding box padded by `domainPadding` times its largest side on
/// every side. Immutable; thread-safe.
class SmoothSurface final : public SquaredDistanceTarget {
 public:
  /// Target from a built surface (shared). `samplesPerEdge` (2..32) sets the starting samples:
  /// the barycentric lattice with that many intervals per face edge. Throws InputError for a null
  /// surface, a negative or non-finite padding, or samplesPerEdge out of range.
  explicit SmoothSurface(std::shared_ptr<const PseudoManifold> surface, double domainPadding = 0.5,
                         int samplesPerEdge = 8);
  ~SmoothSurface() override;
  SmoothSurface(SmoothSurface&&) noexcept;
  SmoothSurface& operator=(SmoothSurface&&) noexcept;

  TargetKind kind() const override { return TargetKind::Surface; }
  Eigen::AlignedBox3d domain() const override { return domain_; }
  Approximant approximantAt(const Eigen::Vector3d& point) const override;
  std::string describe() const override;

  /// The approximant at `point` without the domain check (for field construction over a padded
  /// box). Throws InputError when `point` is not finite.
  Approximant approximantAtAnyPoint(const Eigen::Vector3d& point) const;
  /// The projection of `point` onto the surface (footpoint, face point, distance), by Newton's
  /// method from the nearest of the target's surface samples.
  PseudoManifold::Projection project(const Eigen::Vector3d& point) const;
  /// The approximant at `point` from its projection onto the surface (as approximantAt() makes
  /// it): footpoint, signed distance, the surface's normal, e1, k1, k2 and flags.
  static Approximant approximantOf(const Eigen::Vector3d& point,
                                   const PseudoManifold::Projection& projection);

  const PseudoManifold& surface() const { return *surface_; }
  /// Bounding box of the surface's samples.
  const Eigen::AlignedBox3d& surfaceBounds() const { return bounds_; }
  /// Optional label for describe() (e.g. the input file name).
  void setLabel(std::string label) { label_ = std::move(label); }

 private:
  std::shared_ptr<const PseudoManifold> surface_;
  std::vector<FacePoint> samples_;
  std::unique_ptr<detail::NearestPointTree> tree_;
  Eigen::AlignedBox3d bounds_;
  Eigen::AlignedBox3d domain_;
  std::string label_;
};

}  // namespace d2vdb
