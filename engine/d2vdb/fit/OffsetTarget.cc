#include "d2vdb/fit/OffsetTarget.h"

#include <cmath>
#include <sstream>
#include <utility>

#include "d2vdb/core/Error.h"

namespace d2vdb {

OffsetTarget::OffsetTarget(const SquaredDistanceTarget& base, double r) : base_(base), offset_(r) {
  if (base.kind() == TargetKind::Points) {
    throw InputError("offsets are supported for curve and surface targets, not point sets");
  }
  if (!std::isfinite(r) || r == 0.0 || (base.kind() == TargetKind::Curve && r < 0.0)) {
    std::ostringstream message;
    message << "the offset distance must be finite and "
            << (base.kind() == TargetKind::Curve ? "positive" : "non-zero") << ", got " << r;
    throw InputError(message.str());
  }
}

namespace {

/// The offset curvature k / (1 + r k), clamped (and flagged) where the offset reaches or passes
/// the centre of curvature.
double offsetCurvature(double k, double r, std::uint16_t& flags) {
  const double denominator = 1.0 + r * k;
  if (denominator > 1e-6) return k / denominator;
  flags |= kFlagCutLocus;
  return k / 1e-6;
}

}  // namespace

Approximant OffsetTarget::approximantAt(const Eigen::Vector3d& point) const {
  const Approximant base = base_.approximantAt(point);
  if (base.kind == TargetKind::Surface) {
    Approximant offset = base;
    offset.origin = point;
    offset.footpoint = base.footpoint + offset_ * base.normal;
    offset.distance = base.distance - offset_;
    if ((base.flags & kFlagEndPoint) == 0) {
      offset.k1 = offsetCurvature(base.k1, offset_, offset.flags);
      offset.k2 = offsetCurvature(base.k2, offset_, offset.flags);
      if (offset.k2 > offset.k1) {  // keep k1 >= k2 with e2 = n x e1
        std::swap(offset.k1, offset.k2);
        offset.tangent = base.bitangent();
      }
    }
    return offset;
  }
  Approximant offset;
  offset.kind = TargetKind::Surface;
  offset.origin = point;
  offset.flags = base.flags;
  offset.normal = base.normal;
  offset.footpoint = base.footpoint + offset_ * base.normal;
  offset.distance = base.distance - offset_;
  if ((base.flags & kFlagEndPoint) != 0) {
    // Nearest point of the tube's end cap region: a point distance, kept as the PDM form.
    offset.tangent = base.tangent;
    return offset;
  }
  // Re-orthogonalise the tangent against the normal (they are orthogonal for interior footpoints).
  Eigen::Vector3d tangent = base.tangent - base.tangent.dot(base.normal) * base.normal;
  offset.tangent =
      tangent.norm() > 0.0 ? Eigen::Vector3d(tangent.normalized()) : base.normal.unitOrthogonal();
  const double kt = base.tangentCurvature();
  const double denominator = 1.0 + offset_ * kt;
  if (denominator > 1e-6) {
    offset.k1 = kt / denominator;
  } else {
    offset.k1 = kt / 1e-6;
    offset.flags |= kFlagCutLocus;
  }
  offset.k2 = 1.0 / offset_;
  return offset;
}

std::string OffsetTarget::describe() const {
  std::ostringstream text;
  text << "offset at distance " << offset_ << " of " << base_.describe();
  return text.str();
}

}  // namespace d2vdb
