// Exact approximants of B-spline surface targets (SurfaceTarget.h).
#include "d2vdb/field/SurfaceTarget.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/field/detail/DomainError.h"
#include "d2vdb/measure/SurfaceProjection.h"
#include "d2vdb/spline/SurfaceGeometry.h"

namespace d2vdb {
namespace {

// Messages show points with 9 significant digits.
constexpr int kSurfaceDigits = 9;

}  // namespace

Approximant surfaceApproximantFromFrame(const SurfaceFrame& frame, bool onBoundary,
                                        const Eigen::Vector3d& point) {
  Approximant result;
  result.kind = TargetKind::Surface;
  result.origin = point;
  result.footpoint = frame.point;
  if (onBoundary || !frame.regular) {
    // A point distance: toward the query point, or along the normal when it lies on the edge.
    const Eigen::Vector3d offset = point - frame.point;
    result.flags |= kFlagEndPoint;
    result.distance = offset.norm();
    result.normal =
        result.distance > 0.0 ? Eigen::Vector3d(offset / result.distance) : frame.normal;
    result.tangent = result.normal.unitOrthogonal();
    return result;
  }
  result.normal = frame.normal;
  result.tangent = frame.e1;
  result.k1 = frame.k1;
  result.k2 = frame.k2;
  result.distance = (point - frame.point).dot(frame.normal);
  return result;
}

SurfaceTarget::SurfaceTarget(const BSplineSurface& surface, double domainPadding) {
  if (!(domainPadding >= 0.0) || !std::isfinite(domainPadding)) {
    throw InputError("surface target: the domain padding must be a finite number >= 0");
  }
  for (const Eigen::Vector3d& point : surface.controlPoints()) surfaceBounds_.extend(point);
  if (!(surfaceBounds_.sizes().maxCoeff() > 0.0)) {
    throw InputError("surface target: all control points coincide at " +
                     formatPoint(surface.controlPoints().front(), kSurfaceDigits) +
                     "; the surface is a point");
  }
  projector_ = std::make_unique<SurfaceProjector>(surface);
  domain_ = surfaceBounds_;
  const double pad = domainPadding * surfaceBounds_.sizes().maxCoeff();
  domain_.min().array() -= pad;
  domain_.max().array() += pad;
}

SurfaceTarget::~SurfaceTarget() = default;
SurfaceTarget::SurfaceTarget(SurfaceTarget&&) noexcept = default;
SurfaceTarget& SurfaceTarget::operator=(SurfaceTarget&&) noexcept = default;

const BSplineSurface& SurfaceTarget::surface() const {
  return projector_->surface();
}

std::string SurfaceTarget::describe() const {
  const BSplineSurface& s = surface();
  std::ostringstream text;
  text << "B-spline surface (degree " << s.degreeU() << " x " << s.degreeV() << ", " << s.countU()
       << " x " << s.countV() << " control points)";
  if (!label_.empty()) text << " from " << label_;
  return text.str();
}

Approximant SurfaceTarget::approximantAt(const Eigen::Vector3d& point) const {
  if (!point.allFinite()) throw InputError("surface target: the query point is not finite");
  if (!domain_.contains(point)) {
    detail::throwOutsideDomain(point, domain_, describe(), kSurfaceDigits);
  }
  return approximantAtAnyPoint(point);
}

Approximant SurfaceTarget::approximantAtAnyPoint(const Eigen::Vector3d& point) const {
  if (!point.allFinite()) throw InputError("surface target: the query point is not finite");
  const SurfaceFootpoint footpoint = projector_->nearest(point);
  SurfaceFrame frame = surfaceFrame(surface(), footpoint.u, footpoint.v);
  frame.point = footpoint.point;  // the projector's evaluation of the same point
  return surfaceApproximantFromFrame(frame, footpoint.onBoundary, point);
}

std::vector<Eigen::Vector3d> SurfaceTarget::samplePoints(int samplesU, int samplesV) const {
  return surface().sample(samplesU, samplesV);
}

}  // namespace d2vdb
