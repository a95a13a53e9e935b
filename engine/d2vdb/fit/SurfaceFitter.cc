// The surface fitters: the target problem (SDM I) and the point-cloud problem (SDM II, footpoints
// on the active surface), run by the shared fit loop.
#include "d2vdb/fit/SurfaceFitter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/SurfaceTarget.h"
#include "d2vdb/fit/detail/SplineFit.h"
#include "d2vdb/fit/detail/SurfaceFitLoop.h"
#include "d2vdb/fit/detail/SurfaceReparametrization.h"
#include "d2vdb/fit/detail/SurfaceSensorBasis.h"
#include "d2vdb/fit/detail/TargetProblem.h"
#include "d2vdb/measure/SurfaceProjection.h"
#include "d2vdb/spline/BasisFunctions.h"
#include "d2vdb/spline/SurfaceGeometry.h"

namespace d2vdb {
namespace {

/// Whether u is an end of the surface's domain in u and that direction is open.
bool onOpenBoundaryU(const BSplineSurface& surface, double u) {
  const ParameterInterval domain = surface.domainU();
  return !surface.isClosedU() && (u <= domain.start || u >= domain.end);
}

/// Whether v is an end of the surface's domain in v and that direction is open.
bool onOpenBoundaryV(const BSplineSurface& surface, double v) {
  const ParameterInterval domain = surface.domainV();
  return !surface.isClosedV() && (v <= domain.start || v >= domain.end);
}

bool onOpenBoundary(const BSplineSurface& surface, double u, double v) {
  return onOpenBoundaryU(surface, u) || onOpenBoundaryV(surface, v);
}

/// Where 1 + d k is below this, the exact curvature terms of SDM I are left out (too near a centre
/// of curvature for the quadratic model to hold).
constexpr double kMinimumCurvatureFactor = 0.1;

// SDM I: sensors at fixed parameters, approximants from the target. For SDM also the exact
// second-order terms that the clamped SDM form leaves out: the form's tangential weights are
// max(0, d k_i / (1 + d k_i)); the Hessian of the squared distance has d k_i / (1 + d k_i) also
// where that is negative (on the concave side), and those negative rank-one terms
// (d k_i / (1 + d k_i)) ((B (x) t_i) . c)^2 let the loop's trust-region steps follow the
// surface's sliding along the target like Newton's method, where the clamped form over-damps it.
class SurfaceTargetProblem final : public detail::TargetProblem {
 public:
  SurfaceTargetProblem(const BSplineSurface& initial, const SquaredDistanceTarget& target,
                       const SurfaceFitOptions& options)
      : TargetProblem(
            target,
            std::make_unique<detail::SurfaceSensorBasis>(
                initial, detail::uniformSurfaceSensorParameters(initial, options.sensorsPerSpan)),
            options.method, options.pdmWeight),
        exactSecondOrder_(options.exactSecondOrder && options.method == FitMethod::SDM) {}

  void linearize(const std::vector<Eigen::Vector3d>& controlPoints,
                 detail::FitLinearization& linearization) override {
    const std::vector<Approximant>& approximants = approximantsAt(controlPoints);
    setForms(approximants, linearization);
    const std::size_t count = approximants.size();
    detail::RankOneTerms& secondOrder = linearization.secondOrder;
    secondOrder.reset(static_cast<int>(count), exactSecondOrder_ ? 3 : 0, true);
    if (!exactSecondOrder_) return;
    std::vector<double> weights(2 * count, 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t k = range.begin(); k != range.end(); ++k) {
                          const Approximant& approximant = approximants[k];
                          if ((approximant.flags & kFlagEndPoint) != 0 ||
                              approximant.kind != TargetKind::Surface) {
                            continue;
                          }
                          const double d = approximant.distance;
                          for (int i = 0; i < 2; ++i) {
                            const double kappa = i == 0 ? approximant.k1 : approximant.k2;
                            const double factor = 1.0 + d * kappa;
                            if (d * kappa < 0.0 && factor > kMinimumCurvatureFactor) {
                              weights[2 * k + static_cast<std::size_t>(i)] = d * kappa / factor;
                            }
                          }
                        }
                      });
    // Sensors with terms, in index order (deterministic layout).
    for (std::size_t k = 0; k < count; ++k) {
      int terms = 0;
      for (int i = 0; i < 2; ++i) {
        const double alpha = weights[2 * k + static_cast<std::size_t>(i)];
        if (alpha == 0.0) continue;
        const Approximant& approximant = approximants[k];
        const Eigen::Vector3d direction =
            i == 0 ? approximant.tangent : Eigen::Vector3d(approximant.bitangent());
        secondOrder.coefficients.push_back(alpha);  // u = (basis weights) (x) direction
        for (int c = 0; c < 3; ++c) secondOrder.vectors.push_back(direction[c]);
        ++terms;
      }
      secondOrder.start[k + 1] = secondOrder.start[k] + terms;
    }
  }

 private:
  bool exactSecondOrder_;
};

/// Smallest eigenvalue of the footpoint's parameter Hessian M relative to the first fundamental
/// form (M - kMinimumFocalFactor I_1 must be positive definite) for the exact second-order terms:
/// nearer to a centre of curvature the footpoint is ill-conditioned and the terms are left out.
constexpr double kMinimumFocalFactor = 0.1;
/// Rank-one second-order terms per data point: two for the footpoint's parameters, two for the
/// tangential weights the SDM form leaves out.
constexpr int kTermsPerPoint = 4;

/// The surface at a footpoint: its position and derivatives to second order and, for each
/// control point j of the footpoint's knot cell, the basis values B_j, dB_j/du and dB_j/dv.
struct FootpointExpansion {
  SurfaceDerivatives derivatives;
  std::vector<double> value, valueU, valueV;
};

/// A data point's second-order terms (PointProblem::linearize): `length` entries per vector.
struct PointTerms {
  double* vectors;
  double* coefficients;
  std::size_t length;
};

// SDM II: sensors at the data points' footpoints on the active surface, refreshed every
// iteration; for SDM the exact second-order terms of the squared distance to the moving surface.
class PointProblem final : public detail::FitProblem {
 public:
  PointProblem(const BSplineSurface& initial, const std::vector<Eigen::Vector3d>& points,
               const SurfaceFitOptions& options)
      : points_(points),
        surface_(initial),
        method_(options.method),
        pdmWeight_(options.pdmWeight),
        exactSecondOrder_(options.exactSecondOrder && options.method == FitMethod::SDM) {}

  // With r = S(u, v) - X, B the basis values at the footpoint and B_u, B_v their derivatives, the
  // squared distance with the footpoint's parameters eliminated has the Hessian (half of it, in
  // the forms' units) over the footpoint's control points
  //   I (x) B B^T - G^T M^-1 G,  G = [B (x) S_u + B_u (x) r; B (x) S_v + B_v (x) r],
  //   M = [S_u.S_u + r.S_uu, S_u.S_v + r.S_uv; S_u.S_v + r.S_uv, S_v.S_v + r.S_vv]
  // (the Schur complement of the joint Hessian in the control points and (u, v)). The SDM form
  // is A = I - sum (1 - w_i) t_i t_i^T over its tangential directions, so the rest is, with the
  // eigen-decompositions M = sum l_i m_i m_i^T and I - A = sum mu_j a_j a_j^T:
  //   - sum_i (m_i . G c)^2 / l_i + sum_j mu_j ((B (x) a_j) . c)^2.
  void linearize(const std::vector<Eigen::Vector3d>& controlPoints,
                 detail::FitLinearization& linearization) override {
    surface_.setControlPoints(controlPoints);
    const std::size_t count = points_.size();
    std::vector<Eigen::Vector2d> parameters(count);
    for (std::size_t k = 0; k < count; ++k) {
      parameters[k] = Eigen::Vector2d(current_[k].u, current_[k].v);
    }
    basis_.emplace(surface_, std::move(parameters));
    linearization.basis = &*basis_;
    linearization.forms.resize(count);
    resetSecondOrder(linearization.secondOrder);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        FootpointExpansion footpoint;
                        for (std::size_t k = range.begin(); k != range.end(); ++k) {
                          linearizeAt(k, controlPoints, footpoint, linearization);
                        }
                      });
  }

  detail::DataError measure(const std::vector<Eigen::Vector3d>& controlPoints) override {
    BSplineSurface candidate = surface_;
    candidate.setControlPoints(controlPoints);
    const SurfaceProjector projector(candidate);
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

  void accept() override { current_.swap(candidate_); }

 private:
  /// Control points of a footpoint's knot cell.
  int order() const { return (surface_.degreeU() + 1) * (surface_.degreeV() + 1); }

  /// No second-order terms, or (exactSecondOrder_) kTermsPerPoint zero terms per data point.
  void resetSecondOrder(detail::RankOneTerms& secondOrder) const {
    const std::size_t count = points_.size();
    const int length = 3 * order();
    secondOrder.reset(static_cast<int>(count), length);
    if (!exactSecondOrder_) return;
    for (std::size_t k = 0; k < count; ++k) {
      secondOrder.start[k + 1] = static_cast<int>(kTermsPerPoint * (k + 1));
    }
    secondOrder.coefficients.assign(kTermsPerPoint * count, 0.0);
    secondOrder.vectors.assign(kTermsPerPoint * count * length, 0.0);
  }

  /// The surface's expansion at sensor `sensor` (at `uv`) for `controlPoints`.
  void expand(int sensor, const Eigen::Vector2d& uv,
              const std::vector<Eigen::Vector3d>& controlPoints,
              FootpointExpansion& footpoint) const {
    const KnotVector& knotsU = surface_.knotsU();
    const KnotVector& knotsV = surface_.knotsV();
    const BasisDerivatives bu = basisDerivatives(knotsU, knotsU.findSpan(uv.x()), uv.x(), 2);
    const BasisDerivatives bv = basisDerivatives(knotsV, knotsV.findSpan(uv.y()), uv.y(), 2);
    SurfaceDerivatives& derivatives = footpoint.derivatives;
    derivatives = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                   Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    footpoint.value.resize(order());
    footpoint.valueU.resize(order());
    footpoint.valueV.resize(order());
    int slot = 0;
    for (int a = 0; a <= surface_.degreeU(); ++a) {
      for (int b = 0; b <= surface_.degreeV(); ++b, ++slot) {
        const Eigen::Vector3d& control = controlPoints[basis_->index(sensor, slot)];
        derivatives.point += bu(0, a) * bv(0, b) * control;
        derivatives.du += bu(1, a) * bv(0, b) * control;
        derivatives.dv += bu(0, a) * bv(1, b) * control;
        derivatives.duu += bu(2, a) * bv(0, b) * control;
        derivatives.duv += bu(1, a) * bv(1, b) * control;
        derivatives.dvv += bu(0, a) * bv(2, b) * control;
        footpoint.value[slot] = bu(0, a) * bv(0, b);
        footpoint.valueU[slot] = bu(1, a) * bv(0, b);
        footpoint.valueV[slot] = bu(0, a) * bv(1, b);
      }
    }
  }

  /// Data point k's form and, with exactSecondOrder_, its second-order terms.
  void linearizeAt(std::size_t k, const std::vector<Eigen::Vector3d>& controlPoints,
                   FootpointExpansion& footpoint, detail::FitLinearization& linearization) const {
    const int sensor = static_cast<int>(k);
    const Eigen::Vector2d& uv = basis_->parameter(sensor);  // wrapped when closed
    expand(sensor, uv, controlPoints, footpoint);
    const SurfaceDerivatives& derivatives = footpoint.derivatives;
    const bool boundaryU = onOpenBoundaryU(surface_, uv.x());
    const bool boundaryV = onOpenBoundaryV(surface_, uv.y());
    const Approximant approximant =
        surfaceApproximantFromFrame(surfaceFrame(derivatives), boundaryU || boundaryV, points_[k]);
    // The form measures the surface point against the data point: same matrix, centred at the
    // data point.
    QuadraticForm form = fitForm(approximant, method_, pdmWeight_);
    // A footpoint on one boundary line (not a corner) slides along that line: SDM measures the
    // distance to the line there, orthogonal to it (the tangential weight 0, as TDM; the exact
    // second-order terms below restore the rest).
    const Eigen::Vector3d& lineTangent = boundaryU ? derivatives.dv : derivatives.du;
    const bool onLine =
        boundaryU != boundaryV && method_ == FitMethod::SDM && lineTangent.squaredNorm() > 0.0;
    if (onLine) {
      const Eigen::Vector3d t = lineTangent.normalized();
      form.A = Eigen::Matrix3d::Identity() - t * t.transpose();
    }
    form.b = form.A * points_[k];
    form.c = points_[k].dot(form.b);
    linearization.forms[k] = form;
    if (!exactSecondOrder_ || (boundaryU && boundaryV) || ((boundaryU || boundaryV) && !onLine)) {
      return;
    }
    detail::RankOneTerms& secondOrder = linearization.secondOrder;
    const std::size_t length = secondOrder.length;
    const PointTerms terms{secondOrder.vectors.data() + kTermsPerPoint * k * length,
                           secondOrder.coefficients.data() + kTermsPerPoint * k, length};
    const Eigen::Vector3d r = derivatives.point - points_[k];
    if (onLine) {
      lineTerms(footpoint, boundaryU, lineTangent, r, terms);
    } else {
      interiorTerms(footpoint, form.A, r, terms);
    }
  }

  /// A footpoint on an open boundary line, with one free parameter along it: M = |S_t|^2 +
  /// r . S_tt, g = B S_t + B_t r, and the tangential term the line's form leaves out.
  static void lineTerms(const FootpointExpansion& footpoint, bool boundaryU,
                        const Eigen::Vector3d& lineTangent, const Eigen::Vector3d& r,
                        const PointTerms& terms) {
    const SurfaceDerivatives& derivatives = footpoint.derivatives;
    const Eigen::Vector3d& second = boundaryU ? derivatives.dvv : derivatives.duu;
    const std::vector<double>& along = boundaryU ? footpoint.valueV : footpoint.valueU;
    const double first = lineTangent.squaredNorm();
    const double hessian = first + r.dot(second);
    if (!(hessian > kMinimumFocalFactor * first)) return;
    const Eigen::Vector3d t = lineTangent / std::sqrt(first);
    const std::vector<double>& value = footpoint.value;
    for (std::size_t j = 0; j < value.size(); ++j) {
      const Eigen::Vector3d g = value[j] * lineTangent + along[j] * r;
      for (int c = 0; c < 3; ++c) {
        terms.vectors[j * 3 + c] = g[c];
        terms.vectors[terms.length + j * 3 + c] = value[j] * t[c];
      }
    }
    terms.coefficients[0] = -1.0 / hessian;
    terms.coefficients[1] = 1.0;
  }

  /// A footpoint inside the surface: the two parameter terms and the two tangential terms that
  /// the SDM form `A` leaves out.
  static void interiorTerms(const FootpointExpansion& footpoint, const Eigen::Matrix3d& A,
                            const Eigen::Vector3d& r, const PointTerms& terms) {
    const SurfaceDerivatives& derivatives = footpoint.derivatives;
    Eigen::Matrix2d first;
    first << derivatives.du.squaredNorm(), derivatives.du.dot(derivatives.dv),
        derivatives.du.dot(derivatives.dv), derivatives.dv.squaredNorm();
    Eigen::Matrix2d hessian = first;
    hessian(0, 0) += r.dot(derivatives.duu);
    hessian(0, 1) += r.dot(derivatives.duv);
    hessian(1, 0) += r.dot(derivatives.duv);
    hessian(1, 1) += r.dot(derivatives.dvv);
    const Eigen::Matrix2d guard = hessian - kMinimumFocalFactor * first;
    if (!(guard(0, 0) > 0.0) || !(guard.determinant() > 0.0)) return;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> parameterHessian(hessian);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> deficit(Eigen::Matrix3d::Identity() - A);
    const std::vector<double>& value = footpoint.value;
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector2d m = parameterHessian.eigenvectors().col(i);
      double* const vector = terms.vectors + i * terms.length;
      for (std::size_t j = 0; j < value.size(); ++j) {
        const Eigen::Vector3d g = m.x() * (value[j] * derivatives.du + footpoint.valueU[j] * r) +
                                  m.y() * (value[j] * derivatives.dv + footpoint.valueV[j] * r);
        for (int c = 0; c < 3; ++c) vector[j * 3 + c] = g[c];
      }
      terms.coefficients[i] = -1.0 / parameterHessian.eigenvalues()[i];
    }
    // The two largest eigenvalues of I - A (the third, along the normal, is 0).
    for (int i = 0; i < 2; ++i) {
      const double mu = deficit.eigenvalues()[i + 1];
      if (!(mu > 0.0)) continue;
      const Eigen::Vector3d direction = deficit.eigenvectors().col(i + 1);
      double* const vector = terms.vectors + (2 + i) * terms.length;
      for (std::size_t j = 0; j < value.size(); ++j) {
        for (int c = 0; c < 3; ++c) vector[j * 3 + c] = value[j] * direction[c];
      }
      terms.coefficients[2 + i] = mu;
    }
  }

  const std::vector<Eigen::Vector3d>& points_;
  BSplineSurface surface_;  // the net linearize() was last called with
  FitMethod method_;
  double pdmWeight_;
  bool exactSecondOrder_;
  std::optional<detail::SurfaceSensorBasis> basis_;
  std::vector<SurfaceFootpoint> current_;
  std::vector<SurfaceFootpoint> candidate_;
};

}  // namespace

namespace {

/// The restart of fitSurface (SurfaceFitOptions::reparametrize) runs only when the chord-length
/// spread moves some parameter by more than this fraction of its domain.
constexpr double kReparametrizationShift = 0.01;
/// fitSurface checks the chord-length spread after this many iterations (or when the fit stops
/// before): by then the sensors have reached the target and what is left is mostly sliding.
constexpr int kFirstRunIterations = 8;

/// Whether every sensor of `sensors` on `surface` lies inside `domain`.
bool covers(const detail::SensorMap& sensors, const BSplineSurface& surface,
            const Eigen::AlignedBox3d& domain) {
  for (const Eigen::Vector3d& sensor : sensors.positions(surface.controlPoints())) {
    if (!domain.contains(sensor)) return false;
  }
  return true;
}

/// `first` continued by `second` (run from first's re-parametrised surface): the iterations of
/// both, second's surface, status and reason.
SurfaceFitResult joined(SurfaceFitResult first, SurfaceFitResult second) {
  const int offset = first.iterations();
  for (std::size_t row = 1; row < second.history.size(); ++row) {
    FitIteration iteration = second.history[row];
    iteration.iteration += offset;
    first.history.push_back(iteration);
  }
  for (std::size_t i = 1; i < second.iterates.size(); ++i) {
    first.iterates.push_back(std::move(second.iterates[i]));
  }
  first.surface = std::move(second.surface);
  first.status = second.status;
  // The second run's cap is what was left of the fit's.
  const std::string secondCap = "iteration cap of " + std::to_string(second.iterations());
  const std::size_t at = second.reason.find(secondCap);
  if (second.status == FitStatus::IterationCap && at != std::string::npos) {
    second.reason.replace(at, secondCap.size(),
                          "iteration cap of " + std::to_string(first.iterations()));
  }
  first.reason = second.reason + " (continued after spreading the parameters by chord length at " +
                 "iteration " + std::to_string(offset) + ")";
  return first;
}

}  // namespace

SurfaceFitResult fitSurface(const BSplineSurface& initial, const SquaredDistanceTarget& target,
                            const SurfaceFitOptions& options) {
  detail::validateSurfaceFit(initial, options);
  enforceSurfaceFitBudget(initial, surfaceSensorCount(initial, options.sensorsPerSpan),
                          options.sensorsPerSpan, options.budget);
  SurfaceTargetProblem problem(initial, target, options);
  problem.requireCovered(initial.controlPoints(), "surface");
  const Eigen::AlignedBox3d domain = target.domain();
  // The first run, interrupted after kFirstRunIterations when the chord-length spread differs
  // from the surface's own by kReparametrizationShift or more.
  std::optional<detail::Reparametrization> spread;
  const auto spreadAt = [&](const std::vector<Eigen::Vector3d>& controlPoints) {
    BSplineSurface current = initial;
    current.setControlPoints(controlPoints);
    spread = detail::chordLengthReparametrized(current);
    return spread->shift >= kReparametrizationShift &&
           covers(problem.sensors(), spread->surface, domain);
  };
  bool interrupted = false;
  SurfaceFitResult first = detail::runSurfaceFit(
      initial, options, problem,
      [&](int iteration, const std::vector<Eigen::Vector3d>& controlPoints) {
        interrupted = options.reparametrize && iteration == kFirstRunIterations &&
                      iteration < options.maxIterations && spreadAt(controlPoints);
        return interrupted;
      });
  const int remaining = options.maxIterations - first.iterations();
  // A first run that stopped by itself before that restarts too, and is kept when the restart
  // ends no closer to the target.
  const bool stoppedEarly = !interrupted && first.status != FitStatus::IterationCap &&
                            first.iterations() > 0 && first.iterations() <= kFirstRunIterations;
  if (!options.reparametrize || remaining <= 0 ||
      !(interrupted || (stoppedEarly && spreadAt(first.surface.controlPoints())))) {
    return first;
  }
  const BSplineSurface& restart = spread->surface;
  SurfaceFitOptions continued = options;
  continued.maxIterations = remaining;
  if (options.progress) {
    const double done = static_cast<double>(first.iterations()) / options.maxIterations;
    const double share = static_cast<double>(remaining) / options.maxIterations;
    continued.progress = [&options, done, share](std::string_view stage, double fraction) {
      options.progress(stage, done + share * fraction);
    };
  }
  SurfaceTargetProblem restartProblem(restart, target, continued);
  SurfaceFitResult second = detail::runSurfaceFit(restart, continued, restartProblem);
  if (stoppedEarly && !(second.history.back().rmsDistance < first.history.back().rmsDistance)) {
    return first;
  }
  return joined(std::move(first), std::move(second));
}

Approximant surfaceApproximantAt(const BSplineSurface& surface, double u, double v,
                                 const Eigen::Vector3d& dataPoint) {
  return surfaceApproximantFromFrame(surfaceFrame(surface, u, v), onOpenBoundary(surface, u, v),
                                     dataPoint);
}

SurfaceFitResult fitSurfaceToPoints(const BSplineSurface& initial,
                                    const std::vector<Eigen::Vector3d>& points,
                                    const SurfaceFitOptions& options) {
  detail::requireDataPoints(points, "a surface");
  const std::size_t unknowns = 3 * initial.controlPoints().size();
  if (points.size() < unknowns) {
    throw InputError("the point cloud has " + std::to_string(points.size()) +
                     " points, fewer than the " + std::to_string(unknowns) +
                     " unknowns of a surface with " + std::to_string(initial.countU()) + " x " +
                     std::to_string(initial.countV()) +
                     " control points; use fewer control points or more data");
  }
  detail::validateSurfaceFit(initial, options);
  enforceSurfaceFitBudget(initial, static_cast<double>(points.size()), 0, options.budget);
  PointProblem problem(initial, points, options);
  return detail::runSurfaceFit(initial, options, problem);
}

double surfaceSensorCount(const BSplineSurface& surface, int sensorsPerSpan) {
  const auto direction = [sensorsPerSpan](const KnotVector& knots, bool closed) {
    const double spans = static_cast<double>(knots.breakpoints().size()) - 1.0;
    return spans * sensorsPerSpan + (closed ? 0.0 : 2.0);
  };
  return direction(surface.knotsU(), surface.isClosedU()) *
         direction(surface.knotsV(), surface.isClosedV());
}

double estimateSurfaceFitMemoryBytes(const BSplineSurface& surface, double sensors) {
  const double controlPoints = static_cast<double>(surface.controlPoints().size());
  return kSurfaceFitBytesPerSensor * sensors +
         kSurfaceFitBytesPerControlPoint15 * std::pow(controlPoints, 1.5);
}

void enforceSurfaceFitBudget(const BSplineSurface& surface, double sensors, int sensorsPerSpan,
                             const ResourceBudget& budget) {
  const double limit = static_cast<double>(budget.maxMemoryBytes);
  BudgetRequest request;
  request.estimatedBytes = estimateSurfaceFitMemoryBytes(surface, sensors);
  if (budget.maxMemoryBytes == 0 || request.estimatedBytes <= limit) return;
  const std::string grid =
      std::to_string(surface.countU()) + " x " + std::to_string(surface.countV());
  request.subject = "fitting a surface of " + grid + " control points to " +
                    std::to_string(static_cast<long long>(sensors)) +
                    (sensorsPerSpan > 0 ? " sensors (" + std::to_string(sensorsPerSpan) +
                                              "^2 per knot cell, --sensors)"
                                        : std::string(" data points"));
  const long long fittingSensors =
      sensorsPerSpan > 0
          ? largestFitting(1, sensorsPerSpan,
                           [&](long long s) {
                             return estimateSurfaceFitMemoryBytes(
                                        surface,
                                        surfaceSensorCount(surface, static_cast<int>(s))) <= limit;
                           })
          : 0;
  if (fittingSensors >= 1) {
    request.remedy = "use --sensors " + std::to_string(fittingSensors) + " or fewer";
  } else {
    // Scale both counts by one factor: the sensors per control point stay as they are.
    const double perControlPoint = sensors / static_cast<double>(surface.controlPoints().size());
    const long long side =
        largestFitting(2, std::max(surface.countU(), surface.countV()), [&](long long n) {
          const double count = static_cast<double>(n) * static_cast<double>(n);
          return kSurfaceFitBytesPerSensor * perControlPoint * count +
                     kSurfaceFitBytesPerControlPoint15 * std::pow(count, 1.5) <=
                 limit;
        });
    request.remedy =
        side >= 2 ? "use fewer control points (--ctrl), about " + std::to_string(side) + "," +
                        std::to_string(side) + " or fewer" +
                        (sensorsPerSpan > 0 ? std::string(", or fewer --sensors") : std::string(""))
                  : "use fewer control points (--ctrl)";
  }
  enforceMemoryBudget(request, budget);
}

}  // namespace d2vdb
