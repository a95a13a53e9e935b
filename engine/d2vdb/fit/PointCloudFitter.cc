#include "d2vdb/fit/PointCloudFitter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/fit/detail/FitLoop.h"
#include "d2vdb/measure/PointProjection.h"

namespace d2vdb {

Approximant curveApproximantAt(const BSplineCurve& curve, double t,
                               const Eigen::Vector3d& dataPoint) {
  const CurveDerivatives derivatives = curve.derivatives(t);
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
  } else if (curve.dimension() == 2) {
    normal = Eigen::Vector3d(-tangent.y(), tangent.x(), 0.0).normalized();
  } else {
    normal = tangent.unitOrthogonal();
  }
  approximant.normal = normal;
  const ParameterInterval domain = curve.domain();
  if (!curve.isClosed() && (t <= domain.start || t >= domain.end)) {
    approximant.flags |= kFlagEndPoint;
  }
  return approximant;
}

namespace {

struct Footpoint {
  SegmentPoint location;
  double parameter = 0.0;
  double squaredDistance = 0.0;
};

// Sensors at the data points' footpoints on the active curve, refreshed every iteration.
class PointProblem final : public detail::FitProblem {
 public:
  explicit PointProblem(const std::vector<Eigen::Vector3d>& points) : points_(points) {}

  void linearize(const BSplineCurve& curve, const CurveFitOptions& options,
                 std::vector<double>& parameters, std::vector<QuadraticForm>& forms) override {
    parameters.resize(points_.size());
    forms.resize(points_.size());
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
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t k = range.begin(); k != range.end(); ++k) {
                          const double t = current_[k].parameter;
                          parameters[k] = t;
                          const Approximant approximant = curveApproximantAt(curve, t, points_[k]);
                          // The form measures the curve point against the data point: same
                          // matrix, centred at the data point.
                          QuadraticForm form =
                              fitForm(approximant, options.method, options.pdmWeight);
                          form.b = form.A * points_[k];
                          form.c = points_[k].dot(form.b);
                          forms[k] = form;
                        }
                      });
  }

  detail::DataError measure(const BSplineCurve& curve) override {
    const CurveProjector projector(curve);
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
    detail::DataError error;
    error.count = static_cast<int>(points_.size());
    for (const Footpoint& footpoint : candidate_) {
      error.sum += footpoint.squaredDistance;
      error.maxSquared = std::max(error.maxSquared, footpoint.squaredDistance);
    }
    if (!curve.isClosed()) {  // the end terms of linearize()
      const ParameterInterval domain = curve.domain();
      for (const double t : {domain.start, domain.end}) {
        const Eigen::Vector3d end = curve.evaluate(t);
        error.sum += (points_[nearestDataPoint(end)] - end).squaredNorm();
        error.count += 1;
      }
    }
    if (!std::isfinite(error.sum)) error.valid = false;
    return error;
  }

  void accept() override { current_ = candidate_; }

  // Index of the data point nearest to x (lowest index on ties); a linear scan.
  std::size_t nearestDataPoint(const Eigen::Vector3d& x) const {
    std::size_t best = 0;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < points_.size(); ++k) {
      const double d = (points_[k] - x).squaredNorm();
      if (d < bestDistance) bestDistance = d, best = k;
    }
    return best;
  }

 private:
  const std::vector<Eigen::Vector3d>& points_;
  std::vector<Footpoint> current_;
  std::vector<Footpoint> candidate_;
};

}  // namespace

CurveFitResult fitCurveToPoints(const BSplineCurve& initial,
                                const std::vector<Eigen::Vector3d>& points,
                                const CurveFitOptions& options) {
  if (points.empty()) {
    throw InputError("the point cloud is empty: there is nothing to fit a curve to");
  }
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!points[k].allFinite()) {
      throw InputError("data point " + std::to_string(k) + " has a non-finite coordinate");
    }
    if (initial.dimension() == 2 && points[k].z() != 0.0) {
      throw InputError("data point " + std::to_string(k) +
                       " has z != 0 but the curve is 2D; fit a 3D curve or project the data");
    }
  }
  detail::validateFitOptions(options);
  detail::requireNonDegenerate(initial, "the initial curve");
  PointProblem problem(points);
  return detail::runFitLoop(initial, options, problem);
}

}  // namespace d2vdb
