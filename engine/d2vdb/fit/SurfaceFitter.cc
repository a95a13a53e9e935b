#include "d2vdb/fit/SurfaceFitter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/fit/SurfaceSensorBasis.h"
#include "d2vdb/fit/detail/FitLoop.h"
#include "d2vdb/measure/SurfaceProjection.h"
#include "d2vdb/spline/SurfaceGeometry.h"

namespace d2vdb {
namespace {

// Messages show points with 9 significant digits.
std::string pointText(const Eigen::Vector3d& p) {
  return formatPoint(p, 9);
}

// SDM I: sensors at fixed parameters, approximants from the target.
class TargetProblem final : public detail::SurfaceFitProblem {
 public:
  TargetProblem(const BSplineSurface& initial, const SquaredDistanceTarget& target,
                const SurfaceFitOptions& options)
      : target_(target),
        domain_(target.domain()),
        basis_(initial, uniformSurfaceSensorParameters(initial, options.sensorsPerSpan)),
        method_(options.method),
        pdmWeight_(options.pdmWeight) {}

  const SurfaceSensorBasis& basis() const { return basis_; }
  const SensorMap* fixedBasis() const override { return &basis_; }
  double resolution() const override { return target_.resolution(); }

  void linearize(const BSplineSurface& surface, const SurfaceFitOptions& options,
                 std::vector<Eigen::Vector2d>& parameters,
                 std::vector<QuadraticForm>& forms) override {
    parameters = basis_.parameters();
    // The loop linearises the surface it last accepted, whose forms measure() computed.
    if (surface.controlPoints() == acceptedControlPoints_ && acceptedFormsValid_ &&
        options.method == method_ && options.pdmWeight == pdmWeight_) {
      forms.swap(acceptedForms_);
      acceptedFormsValid_ = false;
      return;
    }
    const std::vector<Approximant> approximants =
        target_.approximantsAt(basis_.positions(surface.controlPoints()));
    forms.resize(approximants.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, approximants.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t k = range.begin(); k != range.end(); ++k) {
                          forms[k] = fitForm(approximants[k], options.method, options.pdmWeight);
                        }
                      });
  }

  // One parallel pass: sensor positions, the domain check, the approximants there, the squared
  // distances they give and the fitting forms (kept for linearize() should this surface be
  // accepted).
  detail::DataError measure(const BSplineSurface& surface) override {
    const std::vector<Eigen::Vector3d>& controlPoints = surface.controlPoints();
    const int count = basis_.sensorCount();
    measuredForms_.resize(static_cast<std::size_t>(count));
    squared_.resize(static_cast<std::size_t>(count));
    std::atomic<bool> outside{false};
    tbb::parallel_for(
        tbb::blocked_range<int>(0, count, 32), [&](const tbb::blocked_range<int>& range) {
          for (int k = range.begin(); k != range.end(); ++k) {
            const Eigen::Vector3d x = basis_.position(k, controlPoints);
            if (!domain_.contains(x) || !x.allFinite()) {
              outside = true;
              return;
            }
            const Approximant approximant = target_.approximantAt(x);
            squared_[static_cast<std::size_t>(k)] = approximant.form(ErrorTerm::SDM)(x);
            measuredForms_[static_cast<std::size_t>(k)] = fitForm(approximant, method_, pdmWeight_);
          }
        });
    detail::DataError error;
    error.count = count;
    if (outside) {
      error.valid = false;
      measuredControlPoints_.clear();
      return error;
    }
    for (const double value : squared_) {  // fixed order: deterministic sum
      error.sum += value;
      error.maxSquared = std::max(error.maxSquared, value);
    }
    measuredControlPoints_ = controlPoints;
    return error;
  }

  void accept() override {
    acceptedControlPoints_.swap(measuredControlPoints_);
    acceptedForms_.swap(measuredForms_);
    acceptedFormsValid_ = !acceptedControlPoints_.empty();
  }

 private:
  const SquaredDistanceTarget& target_;
  Eigen::AlignedBox3d domain_;
  SurfaceSensorBasis basis_;
  FitMethod method_;
  double pdmWeight_;
  std::vector<Eigen::Vector3d> measuredControlPoints_, acceptedControlPoints_;
  std::vector<QuadraticForm> measuredForms_, acceptedForms_;
  bool acceptedFormsValid_ = false;
  std::vector<double> squared_;
};

// SDM II: sensors at the data points' footpoints on the active surface, refreshed every
// iteration.
class PointProblem final : public detail::SurfaceFitProblem {
 public:
  explicit PointProblem(const std::vector<Eigen::Vector3d>& points) : points_(points) {}

  void linearize(const BSplineSurface& surface, const SurfaceFitOptions& options,
                 std::vector<Eigen::Vector2d>& parameters,
                 std::vector<QuadraticForm>& forms) override {
    parameters.resize(points_.size());
    forms.resize(points_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t k = range.begin(); k != range.end(); ++k) {
                          const SurfaceFootpoint& footpoint = current_[k];
                          parameters[k] = Eigen::Vector2d(footpoint.u, footpoint.v);
                          const Approximant approximant =
                              surfaceApproximantAt(surface, footpoint.u, footpoint.v, points_[k]);
                          // The form measures the surface point against the data point: same
                          // matrix, centred at the data point.
                          QuadraticForm form =
                              fitForm(approximant, options.method, options.pdmWeight);
                          form.b = form.A * points_[k];
                          form.c = points_[k].dot(form.b);
                          forms[k] = form;
                        }
                      });
  }

  detail::DataError measure(const BSplineSurface& surface) override {
    const SurfaceProjector projector(surface);
    candidate_ = projector.nearest(
        points_, current_.size() == points_.size() ? current_ : std::vector<SurfaceFootpoint>{});
    detail::DataError error;
    error.count = static_cast<int>(points_.size());
    for (const SurfaceFootpoint& footpoint : candidate_) {  // fixed order: deterministic sum
      error.sum += footpoint.squaredDistance;
      error.maxSquared = std::max(error.maxSquared, footpoint.squaredDistance);
    }
    if (!std::isfinite(error.sum)) error.valid = false;
    return error;
  }

  void accept() override { current_ = candidate_; }

 private:
  const std::vector<Eigen::Vector3d>& points_;
  std::vector<SurfaceFootpoint> current_;
  std::vector<SurfaceFootpoint> candidate_;
};

}  // namespace

SurfaceFitResult fitSurface(const BSplineSurface& initial, const SquaredDistanceTarget& target,
                            const SurfaceFitOptions& options) {
  detail::validateFitOptions(options);
  detail::requireNonDegenerate(initial, "the initial surface");
  TargetProblem problem(initial, target, options);
  const Eigen::AlignedBox3d domain = target.domain();
  const std::vector<Eigen::Vector3d> sensors = problem.basis().positions(initial.controlPoints());
  for (std::size_t k = 0; k < sensors.size(); ++k) {
    if (!domain.contains(sensors[k])) {
      const Eigen::Vector3d outside =
          (sensors[k] - sensors[k].cwiseMax(domain.min()).cwiseMin(domain.max())).cwiseAbs();
      throw InputError("the target (" + target.describe() +
                       ") does not cover the initial surface: sensor " + std::to_string(k) +
                       " at " + pointText(sensors[k]) + " lies " + std::to_string(outside.norm()) +
                       " outside its working domain " + pointText(domain.min()) + " - " +
                       pointText(domain.max()) +
                       "; start from a surface inside the domain or build the target with more "
                       "padding");
    }
  }
  return detail::runFitLoop(initial, options, problem);
}

Approximant surfaceApproximantAt(const BSplineSurface& surface, double u, double v,
                                 const Eigen::Vector3d& dataPoint) {
  const SurfaceFrame frame = surfaceFrame(surface, u, v);
  Approximant approximant;
  approximant.kind = TargetKind::Surface;
  approximant.origin = dataPoint;
  approximant.footpoint = frame.point;
  const ParameterInterval domainU = surface.domainU();
  const ParameterInterval domainV = surface.domainV();
  const bool onBoundary = (!surface.isClosedU() && (u <= domainU.start || u >= domainU.end)) ||
                          (!surface.isClosedV() && (v <= domainV.start || v >= domainV.end));
  if (onBoundary || !frame.regular) {
    const Eigen::Vector3d offset = dataPoint - frame.point;
    approximant.flags |= kFlagEndPoint;
    approximant.distance = offset.norm();
    approximant.normal =
        approximant.distance > 0.0 ? Eigen::Vector3d(offset / approximant.distance) : frame.normal;
    approximant.tangent = approximant.normal.unitOrthogonal();
    return approximant;
  }
  approximant.normal = frame.normal;
  approximant.tangent = frame.e1;
  approximant.k1 = frame.k1;
  approximant.k2 = frame.k2;
  approximant.distance = (dataPoint - frame.point).dot(frame.normal);
  return approximant;
}

SurfaceFitResult fitSurfaceToPoints(const BSplineSurface& initial,
                                    const std::vector<Eigen::Vector3d>& points,
                                    const SurfaceFitOptions& options) {
  if (points.empty()) {
    throw InputError("the point cloud is empty: there is nothing to fit a surface to");
  }
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!points[k].allFinite()) {
      throw InputError("data point " + std::to_string(k) + " has a non-finite coordinate");
    }
  }
  const std::size_t unknowns = 3 * initial.controlPoints().size();
  if (points.size() < unknowns) {
    throw InputError("the point cloud has " + std::to_string(points.size()) +
                     " points, fewer than the " + std::to_string(unknowns) +
                     " unknowns of a surface with " + std::to_string(initial.countU()) + " x " +
                     std::to_string(initial.countV()) +
                     " control points; use fewer control points or more data");
  }
  detail::validateFitOptions(options);
  detail::requireNonDegenerate(initial, "the initial surface");
  PointProblem problem(points);
  return detail::runFitLoop(initial, options, problem);
}

}  // namespace d2vdb
