#include "d2vdb/field/SmoothSurface.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/field/detail/DomainError.h"
#include "d2vdb/field/detail/NearestPointTree.h"
#include "d2vdb/manifold/SourceDistance.h"

namespace d2vdb {
namespace {

/// Significant digits of the numbers in messages.
constexpr int kSmoothSurfaceDigits = 6;

/// Below this 1 + d k_i the SDM weights are near a centre of curvature (the field's threshold).
constexpr double kCutLocusMargin = 0.05;

}  // namespace

SmoothSurface::SmoothSurface(std::shared_ptr<const PseudoManifold> surface, double domainPadding,
                             int samplesPerEdge)
    : surface_(std::move(surface)) {
  if (!surface_) throw InputError("the smooth-surface target needs a surface");
  if (!std::isfinite(domainPadding) || domainPadding < 0.0) {
    throw InputError("the domain padding must be a finite number >= 0");
  }
  if (samplesPerEdge < 2 || samplesPerEdge > 32) {
    throw InputError("the smooth-surface target needs 2..32 samples per face edge, not " +
                     std::to_string(samplesPerEdge));
  }
  const HalfEdgeMesh& mesh = surface_->mesh();
  const std::vector<Eigen::Vector3d> lattice = faceLattice(samplesPerEdge);
  samples_.reserve(mesh.faceCount() * lattice.size());
  for (HalfEdgeMesh::Index f = 0; f < mesh.faceCount(); ++f) {
    for (const Eigen::Vector3d& bary : lattice) samples_.push_back({f, bary});
  }
  std::vector<Eigen::Vector3f> points(samples_.size());
  tbb::parallel_for(std::size_t{0}, samples_.size(), [&](std::size_t i) {
    points[i] = surface_->position(samples_[i]).cast<float>();
  });
  for (const Eigen::Vector3f& p : points) bounds_.extend(p.cast<double>());
  tree_ = std::make_unique<detail::NearestPointTree>(points);
  const double pad = domainPadding * bounds_.sizes().maxCoeff();
  domain_ = Eigen::AlignedBox3d(bounds_.min() - Eigen::Vector3d::Constant(pad),
                                bounds_.max() + Eigen::Vector3d::Constant(pad));
}

SmoothSurface::~SmoothSurface() = default;
SmoothSurface::SmoothSurface(SmoothSurface&&) noexcept = default;
SmoothSurface& SmoothSurface::operator=(SmoothSurface&&) noexcept = default;

std::string SmoothSurface::describe() const {
  std::string text = "smooth surface (" + surface_->sourceName() + ") of " +
                     std::to_string(surface_->mesh().faceCount()) + " faces";
  if (!label_.empty()) text += " from " + label_;
  return text;
}

PseudoManifold::Projection SmoothSurface::project(const Eigen::Vector3d& point) const {
  if (!point.allFinite()) throw InputError("smooth-surface target: the query point is not finite");
  const detail::NearestPointTree::Nearest nearest = tree_->nearest(point.cast<float>(), 0);
  return surface_->project(point, samples_[nearest.index]);
}

Approximant SmoothSurface::approximantAt(const Eigen::Vector3d& point) const {
  if (!point.allFinite()) throw InputError("smooth-surface target: the query point is not finite");
  if (!domain_.contains(point)) {
    detail::throwOutsideDomain(point, domain_, describe(), kSmoothSurfaceDigits);
  }
  return approximantAtAnyPoint(point);
}

Approximant SmoothSurface::approximantAtAnyPoint(const Eigen::Vector3d& point) const {
  return approximantOf(point, project(point));
}

Approximant SmoothSurface::approximantOf(const Eigen::Vector3d& point,
                                         const PseudoManifold::Projection& projection) {
  const SmoothPoint& geometry = projection.geometry;
  Approximant result;
  result.kind = TargetKind::Surface;
  result.origin = point;
  result.footpoint = geometry.position;
  result.normal = geometry.normal;
  result.tangent = geometry.e1;
  result.k1 = geometry.k1;
  result.k2 = geometry.k2;
  const double side = (point - geometry.position).dot(geometry.normal);
  result.distance = side < 0.0 ? -projection.distance : projection.distance;
  if (1.0 + result.distance * result.k1 < kCutLocusMargin ||
      1.0 + result.distance * result.k2 < kCutLocusMargin) {
    result.flags |= kFlagCutLocus;
  }
  if (!projection.converged) result.flags |= kFlagDegradedEstimate;
  return result;
}

}  // namespace d2vdb
