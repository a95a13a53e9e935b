// The level set d = r of a curve target as a fitting target: fitting to the offset of a curve
// (the offset-approximation example of Pottmann, Leopoldseder and Hofer 2002).
#pragma once

#include <string>

#include "d2vdb/field/SquaredDistanceTarget.h"

namespace d2vdb {

/// Squared-distance approximants of the offset {x : d(x) = r} of a curve or surface target `base`.
///
/// Surface targets (signed distance d, outward normal n, principal curvatures k1, k2 at the
/// footpoint s): the offset's footpoint is s + r n, its signed distance d - r, its normal n and its
/// principal curvatures k_i / (1 + r k_i) (the centres of curvature are the base's), so the SDM
/// weights are (d - r) k_i / (1 + d k_i) clamped at 0. r may be negative (inward) as long as the
/// offset has not passed a centre of curvature: where 1 + r k_i <= 1e-6 the curvature is clamped
/// and the approximant flagged kFlagCutLocus. A field answers beyond its narrow band only
/// approximately (ApproximantField.h), so an offset larger than the band is fitted to that
/// accuracy. Boundary (kFlagEndPoint) answers stay point distances, moved by r along their normal.
///
/// Curve targets:
/// At a query point x with base approximant (footpoint s, unit normal n toward x, tangent t,
/// distance d, tangential curvature k_t seen from x), the offset's nearest point is s + r n and
/// its distance |d - r|. The answer is a Surface-kind approximant (the offset of a space curve is
/// a tube; a planar curve's offset in its plane is the tube's section): footpoint s + r n, normal n
/// (outward from the base curve), signed distance d - r (negative between the base curve and the
/// offset), tangent t with curvature k_t / (1 + r k_t) (the centre of curvature is shared with the
/// base curve), bitangent with curvature 1 / r (the tube's circular section; it is outside the
/// plane of a 2D fit, whose forms use the xy block only). So (d - r)^2 is reproduced exactly and
/// the SDM form is the Taylor approximant of (d - r)^2. Where 1 + r k_t <= 0 the offset has passed
/// the centre of curvature (a cusp region): the tangential curvature is clamped and the
/// approximant flagged kFlagCutLocus. End points of open curves stay end points (PDM form).
///
/// The base must outlive this object. Domain and thread-safety are the base's.
class OffsetTarget final : public SquaredDistanceTarget {
 public:
  /// Throws InputError when `base` is a point-set target, r is not finite, or r is not positive
  /// for a curve target (a tube has no inward offset) or zero.
  OffsetTarget(const SquaredDistanceTarget& base, double r);

  TargetKind kind() const override { return TargetKind::Surface; }
  Eigen::AlignedBox3d domain() const override { return base_.domain(); }
  Approximant approximantAt(const Eigen::Vector3d& point) const override;
  std::string describe() const override;
  /// The base target's resolved length.
  double resolvedLength() const override { return base_.resolvedLength(); }

  /// The offset distance r (world units).
  double offset() const { return offset_; }

 private:
  const SquaredDistanceTarget& base_;
  double offset_;
};

}  // namespace d2vdb
