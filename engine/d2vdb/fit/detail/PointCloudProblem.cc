// SDM II's side of the fit loop (detail/PointCloudProblem.h).
#include "d2vdb/fit/detail/PointCloudProblem.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

#include "d2vdb/spline/BasisFunctions.h"

namespace d2vdb::detail {
namespace {

/// Below this fraction of |C'|^2 the footpoint's second-order term D = |C'|^2 + (C - X) . C'' is
/// not trusted (the data point is near a centre of curvature of the curve, where the squared
/// distance is not smooth): the plain SDM term is used there.
constexpr double kMinimumFocalFactor = 0.1;

bool atOpenEnd(const BSplineCurve& curve, double t) {
  const ParameterInterval domain = curve.domain();
  return !curve.isClosed() && (t <= domain.start || t >= domain.end);
}

}  // namespace

Approximant curveApproximantFrom(const CurveDerivatives& derivatives, bool endPoint, int dimension,
                                 const Eigen::Vector3d& dataPoint) {
  Approximant approximant;
  approximant.kind = TargetKind::Curve;
  approximant.origin = dataPoint;
  approximant.footpoint = derivatives.point;
  const double speed = derivatives.first.norm();
  const Eigen::Vector3d tangent =
      speed > 0.0 ? Eigen::Vector3d(derivatives.first / speed) : Eigen::Vector3d::UnitX();
  approximant.tangent = tangent;
  if (speed > 0.0) {
    const Eigen::Vector3d curvatureVector =
        (derivatives.second - derivatives.second.dot(tangent) * tangent) / (speed * speed);
    approximant.k1 = curvatureVector.norm();
    if (approximant.k1 > 0.0) approximant.principalNormal = curvatureVector / approximant.k1;
  }
  const Eigen::Vector3d offset = dataPoint - derivatives.point;
  Eigen::Vector3d normal = offset - offset.dot(tangent) * tangent;
  approximant.distance = offset.norm();
  if (normal.norm() > 1e-14 * std::max(1.0, derivatives.point.norm())) {
    normal.normalize();
  } else if (dimension == 2) {
    normal = Eigen::Vector3d(-tangent.y(), tangent.x(), 0.0).normalized();
  } else {
    normal = tangent.unitOrthogonal();
  }
  approximant.normal = normal;
  if (endPoint) approximant.flags |= kFlagEndPoint;
  return approximant;
}

PointCloudProblem::PointCloudProblem(const BSplineCurve& initial,
                                     const std::vector<Eigen::Vector3d>& points,
                                     const CurveFitOptions& options)
    : points_(points),
      curve_(initial),
      method_(options.method),
      pdmWeight_(options.pdmWeight),
      exactSecondOrder_(options.exactSecondOrder && options.method == FitMethod::SDM),
      footpointCorrection_(exactSecondOrder_ && options.footpointCorrection) {}

void PointCloudProblem::linearize(const std::vector<Eigen::Vector3d>& controlPoints,
                                  FitLinearization& linearization) {
  curve_.setControlPoints(controlPoints);
  const BSplineCurve& curve = curve_;
  const std::size_t count = points_.size();
  std::vector<double> parameters(count);
  for (std::size_t k = 0; k < count; ++k) parameters[k] = current_[k].parameter;
  std::vector<QuadraticForm>& forms = linearization.forms;
  forms.resize(count);
  if (!curve.isClosed()) {
    // The ends of an open curve: pulled (PDM) to their nearest data points, so that the curve
    // does not run on beyond the data, where no data point would hold it.
    const ParameterInterval domain = curve.domain();
    for (const double t : {domain.start, domain.end}) {
      const Eigen::Vector3d& q = points_[nearestDataPoint(curve.evaluate(t))];
      QuadraticForm form;
      form.A = Eigen::Matrix3d::Identity();
      form.b = q;
      form.c = q.squaredNorm();
      parameters.push_back(t);
      forms.push_back(form);
    }
  }
  basis_.emplace(curve, std::move(parameters));
  linearization.basis = &*basis_;

  // SDM II's exact second-order terms per data point (two rank-one terms, see below).
  const int d = curve.dimension();
  const int p = curve.degree();
  const int length = (p + 1) * d;
  RankOneTerms& secondOrder = linearization.secondOrder;
  secondOrder.reset(basis_->sensorCount(), length);
  if (exactSecondOrder_) {
    for (std::size_t k = 0; k < count; ++k)
      secondOrder.start[k + 1] = static_cast<int>(2 * (k + 1));
    for (std::size_t k = count; k < forms.size(); ++k) {
      secondOrder.start[k + 1] = secondOrder.start[k];
    }
    secondOrder.coefficients.assign(2 * count, 0.0);
    secondOrder.vectors.assign(2 * count * static_cast<std::size_t>(length), 0.0);
  }
  const KnotVector& knots = curve.knots();
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, count, 256),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
          const double t = basis_->parameter(static_cast<int>(k));  // wrapped for closed curves
          // The curve's point and derivatives at t from the basis functions' derivatives
          // (wanted below as well).
          const BasisDerivatives basis = basisDerivatives(knots, knots.findSpan(t), t, 2);
          CurveDerivatives derivatives{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                       Eigen::Vector3d::Zero()};
          for (int j = 0; j <= p; ++j) {
            const Eigen::Vector3d& control =
                controlPoints[static_cast<std::size_t>(basis_->index(static_cast<int>(k), j))];
            derivatives.point += basis(0, j) * control;
            derivatives.first += basis(1, j) * control;
            derivatives.second += basis(2, j) * control;
          }
          const Approximant approximant =
              curveApproximantFrom(derivatives, atOpenEnd(curve, t), d, points_[k]);
          // The form measures the curve point against the data point: same matrix, centred at
          // the data point.
          QuadraticForm form = fitForm(approximant, method_, pdmWeight_);
          form.b = form.A * points_[k];
          form.c = points_[k].dot(form.b);
          forms[k] = form;
          if (!exactSecondOrder_ || (approximant.flags & kFlagEndPoint) != 0) continue;
          // The squared distance from X to the curve, with the footpoint parameter t(P)
          // eliminated, has the Hessian (half of it, in the forms' units) over the footpoint's
          // control points
          //   I (x) B B^T - u u^T / D,  u = B (x) C' + B' (x) r,  D = |C'|^2 + r . C'',
          // r = C(t) - X (the Schur complement of the joint Hessian in the control points and
          // t). The SDM form is I - (1 - w) T T^T (w its clamped tangential weight), so the
          // rest is (1 - w) (v . c)^2 - (u . c)^2 / D with v = B (x) T.
          const Eigen::Vector3d& point = derivatives.point;
          const Eigen::Vector3d& first = derivatives.first;
          const Eigen::Vector3d& second = derivatives.second;
          const double speed2 = first.squaredNorm();
          const Eigen::Vector3d r = point - points_[k];
          const double focal = speed2 + r.dot(second);
          if (!(speed2 > 0.0) || !(focal > kMinimumFocalFactor * speed2)) continue;
          const Eigen::Vector3d tangent = first / std::sqrt(speed2);
          const double w = approximant.sdmWeights()[0];
          double* const u = secondOrder.vectors.data() + 2 * k * static_cast<std::size_t>(length);
          double* const v = u + length;
          for (int j = 0; j <= p; ++j) {
            const Eigen::Vector3d uj = basis(0, j) * first + basis(1, j) * r;
            for (int a = 0; a < d; ++a) {
              u[j * d + a] = uj[a];
              v[j * d + a] = basis(0, j) * tangent[a];
            }
          }
          secondOrder.coefficients[2 * k] = -1.0 / focal;
          secondOrder.coefficients[2 * k + 1] = 1.0 - w;
        }
      });
}

DataError PointCloudProblem::measure(const std::vector<Eigen::Vector3d>& controlPoints) {
  BSplineCurve candidate = curve_;
  candidate.setControlPoints(controlPoints);
  const CurveProjector projector(candidate);
  candidate_.resize(points_.size());
  const bool haveHints = current_.size() == points_.size();
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, points_.size(), 128),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
          std::optional<SegmentPoint> hint;
          if (haveHints) hint = current_[k].location;
          const NearestPoint nearest = projector.nearest(points_[k], hint);
          candidate_[k] = {nearest.location, nearest.parameter, nearest.squaredDistance};
        }
      });
  DataError error;
  error.count = static_cast<int>(points_.size());
  for (const Footpoint& footpoint : candidate_) {
    error.sum += footpoint.squaredDistance;
    error.maxSquared = std::max(error.maxSquared, footpoint.squaredDistance);
  }
  candidateEnds_.clear();
  if (!candidate.isClosed()) {  // the end terms of linearize()
    const ParameterInterval domain = candidate.domain();
    for (const double t : {domain.start, domain.end}) {
      const Eigen::Vector3d end = candidate.evaluate(t);
      candidateEnds_.push_back(nearestDataPoint(end));
      error.sum += (points_[candidateEnds_.back()] - end).squaredNorm();
      error.count += 1;
    }
  }
  if (!std::isfinite(error.sum)) error.valid = false;
  return error;
}

bool PointCloudProblem::correction(const std::vector<Eigen::Vector3d>& controlPoints,
                                   FitLinearization& correction) {
  if (!footpointCorrection_ || candidate_.size() != points_.size()) return false;
  BSplineCurve candidate = curve_;
  candidate.setControlPoints(controlPoints);
  const std::size_t count = points_.size();
  std::vector<double> parameters(count);
  for (std::size_t k = 0; k < count; ++k) parameters[k] = candidate_[k].parameter;
  std::vector<Eigen::Vector3d> targets = points_;
  if (!candidate.isClosed()) {
    const ParameterInterval domain = candidate.domain();
    parameters.push_back(domain.start);
    parameters.push_back(domain.end);
    for (const std::size_t end : candidateEnds_) targets.push_back(points_[end]);
  }
  correctionBasis_.emplace(candidate, std::move(parameters));
  correction.basis = &*correctionBasis_;
  correction.forms.resize(targets.size());
  for (std::size_t k = 0; k < targets.size(); ++k) {
    QuadraticForm& form = correction.forms[k];
    form.A = Eigen::Matrix3d::Identity();
    form.b = targets[k];
    form.c = targets[k].squaredNorm();
  }
  correction.secondOrder.reset(correctionBasis_->sensorCount(), 0);
  return true;
}

std::size_t PointCloudProblem::nearestDataPoint(const Eigen::Vector3d& x) const {
  std::size_t best = 0;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < points_.size(); ++k) {
    const double d = (points_[k] - x).squaredNorm();
    if (d < bestDistance) bestDistance = d, best = k;
  }
  return best;
}

}  // namespace d2vdb::detail
