// The iteration shared by the squared-distance fitters (detail/FitLoop.h).
#include "d2vdb/fit/detail/FitLoop.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"

namespace d2vdb {

const char* fitStatusName(FitStatus status) {
  switch (status) {
    case FitStatus::Converged:
      return "converged";
    case FitStatus::Stalled:
      return "stalled";
    case FitStatus::IterationCap:
      return "iteration cap";
  }
  return "unknown";
}

namespace detail {
namespace {

/// Fraction of the target's resolution (a field's voxel) below which a move is not resolved: the
/// approximants' own error (footpoints to a few hundredths of a voxel, piecewise per voxel) makes
/// the objective rough on that scale.
constexpr double kResolvedFraction = 0.01;
/// The automatic bending weight of the first iteration (refined within it).
constexpr double kInitialAutomaticBending = 1e-6;
/// Bounds of the automatic bending weight.
constexpr double kMinimumAutomaticBending = 1e-16;
constexpr double kMaximumAutomaticBending = 1e-2;
/// The automatic bending weight is re-chosen when its bias is off the target by more than this
/// factor, in at most this many solves per iteration.
constexpr double kBiasSlack = 1.25;
constexpr int kBendingRounds = 4;
/// Share of the plain forms in the step's model (1 = forms only) after a step that went well or
/// badly: 1 -> 1/4 -> 1/16 -> 1/64 -> 0 and back.
constexpr double kSmallestFormShare = 1.0 / 64.0;
/// A corrected full step is extrapolated when its decrease exceeds this multiple of the
/// model's predicted decrease, up to this multiple of the step.
constexpr double kExtrapolationGain = 2.0;
constexpr double kLargestExtrapolation = 64.0;

double objectiveOf(const DataError& error, double smoothingEnergy) {
  if (!error.valid || error.count == 0) return std::numeric_limits<double>::infinity();
  return error.sum / error.count + smoothingEnergy;
}

double rmsOf(const DataError& error) {
  return error.count > 0 ? std::sqrt(error.sum / error.count) : 0.0;
}

std::vector<Eigen::Vector3d> moved(const std::vector<Eigen::Vector3d>& points,
                                   const std::vector<Eigen::Vector3d>& displacement, double scale) {
  std::vector<Eigen::Vector3d> result(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) result[i] = points[i] + scale * displacement[i];
  return result;
}

double largestMove(const std::vector<Eigen::Vector3d>& displacement) {
  double largest = 0.0;
  for (const Eigen::Vector3d& c : displacement) largest = std::max(largest, c.norm());
  return largest;
}

double moreForms(double share) {
  return share == 0.0 ? kSmallestFormShare : std::min(1.0, 4.0 * share);
}

double fewerForms(double share) {
  return share <= kSmallestFormShare ? 0.0 : share / 4.0;
}

void validate(const FitLoopSettings& settings, int controlPoints) {
  const auto require = [](bool ok, const std::string& message) {
    if (!ok) throw InputError(message);
  };
  require(settings.dimension == 2 || settings.dimension == 3,
          "the fitting dimension must be 2 or 3");
  require(controlPoints >= 1, "the control net is empty");
  require(settings.maxIterations >= 0, "the iteration cap must not be negative");
  require(std::isfinite(settings.bendingWeight), "the bending weight must be finite");
  require(std::isfinite(settings.automaticBias) && settings.automaticBias > 0.0,
          "the automatic smoothing bias must be finite and positive");
  for (const double value :
       {settings.distanceTolerance, settings.stepTolerance, settings.moveTolerance,
        settings.objectiveTolerance, settings.stepSmoothness, settings.initialDamping}) {
    require(std::isfinite(value) && value >= 0.0,
            "the fit's tolerances, step smoothness and damping must be finite and non-negative");
  }
}

/// The statistical resolution of a least-squares fit with `controlPoints` points' worth of
/// freedom to `count` squared distances of RMS `rms`.
double fitResolution(double rms, int controlPoints, int count) {
  return count > 0 ? rms * std::sqrt(static_cast<double>(controlPoints) / count) : 0.0;
}

/// d_k^T A_k d_k for sensor k's share d_k = sum_j w_kj c_j of the per-control-point displacement
/// `displacement` (z = 0 in 2D) and its form's matrix A_k: the square of the sensor's move in the
/// form's metric.
double squaredSensorMove(const FitLinearization& linearization,
                         const std::vector<Eigen::Vector3d>& displacement, int dimension, int k) {
  const SensorMap& basis = *linearization.basis;
  Eigen::Vector3d delta = Eigen::Vector3d::Zero();
  for (int j = 0; j < basis.order(); ++j) {
    delta += basis.weight(k, j) * displacement[static_cast<std::size_t>(basis.index(k, j))];
  }
  if (dimension == 2) delta.z() = 0.0;
  return delta.dot(linearization.forms[static_cast<std::size_t>(k)].A * delta);
}

/// Chooses the automatic bending weight (detail/FitLoop.h): solves the plain-form model at the
/// current weight (the last one, scaled as the target changed since), measures the shift of its
/// minimiser that the bending term causes, and moves the weight towards the one whose shift is
/// the target (a secant step in log-log, the exponent remembered between iterations), until
/// within kBiasSlack or kBendingRounds solves.
class AutomaticBending {
 public:
  explicit AutomaticBending(double weight) : weight_(weight) {}
  double weight() const { return weight_; }

  void choose(QuadraticModel& model, const FitLinearization& linearization, double target,
              int dimension) {
    // The bias grows with the weight as weight^exponent: when the target moved (it follows the
    // RMS distance), start from the weight that would keep the last bias on the new target.
    if (previousTarget_ > 0.0 && target > 0.0 && weight_ > kMinimumAutomaticBending) {
      const double factor =
          std::clamp(std::pow(target / previousTarget_, 1.0 / exponent_), 0.1, 10.0);
      weight_ = std::clamp(weight_ * factor, kMinimumAutomaticBending, kMaximumAutomaticBending);
    }
    previousTarget_ = target;
    for (int round = 0; round < kBendingRounds; ++round) {
      model.setSmoothingScale(weight_);
      model.solveAssembled(0.0, 0.0);
      const double bias = shiftAtSensors(model.scaledSmoothingShift(), linearization, dimension);
      if (!(target > 0.0)) {  // an exact fit: let the bending fade
        weight_ = std::max(kMinimumAutomaticBending, weight_ / 10.0);
        break;
      }
      if (!(bias > 0.0)) break;  // the bending term has no effect (e.g. a straight line)
      if (previousWeight_ > 0.0 && previousBias_ > 0.0 &&
          std::abs(std::log(weight_ / previousWeight_)) > 0.05) {
        exponent_ = std::clamp(std::log(bias / previousBias_) / std::log(weight_ / previousWeight_),
                               0.3, 1.5);
      }
      previousWeight_ = weight_;
      previousBias_ = bias;
      const double ratio = target / bias;
      if (ratio < kBiasSlack && ratio > 1.0 / kBiasSlack) break;
      const double factor = std::clamp(std::pow(ratio, 1.0 / exponent_), 0.1, 10.0);
      weight_ = std::clamp(weight_ * factor, kMinimumAutomaticBending, kMaximumAutomaticBending);
      if (weight_ == previousWeight_) break;
    }
    model.setSmoothingScale(weight_);
  }

 private:
  /// RMS over the sensors of sqrt(d_k^T A_k d_k), d_k the sensor's share of `shift`.
  static double shiftAtSensors(const std::vector<Eigen::Vector3d>& shift,
                               const FitLinearization& linearization, int dimension) {
    const SensorMap& basis = *linearization.basis;
    const int count = basis.sensorCount();
    if (count == 0) return 0.0;
    // Each sensor's term in parallel, summed in sensor order (the same sum for any thread count).
    std::vector<double> terms(static_cast<std::size_t>(count));
    tbb::parallel_for(tbb::blocked_range<int>(0, count, 1024),
                      [&](const tbb::blocked_range<int>& range) {
                        for (int k = range.begin(); k != range.end(); ++k) {
                          terms[static_cast<std::size_t>(k)] =
                              squaredSensorMove(linearization, shift, dimension, k);
                        }
                      });
    double sum = 0.0;
    for (const double term : terms) sum += term;
    return std::sqrt(std::max(0.0, sum) / count);
  }

  double weight_;
  double previousWeight_ = 0.0;
  double previousBias_ = 0.0;
  double previousTarget_ = 0.0;  ///< the target of the last choice
  double exponent_ = 1.0;
};

/// The largest move of the sensors under the displacement `step`, measured in their forms'
/// metric: max_k sqrt(d_k^T A_k d_k) (for SDM and TDM forms the move across the target).
double largestSensorMove(const FitLinearization& linearization,
                         const std::vector<Eigen::Vector3d>& step, int dimension) {
  const SensorMap& basis = *linearization.basis;
  // The largest of the sensors' values, in parallel (a maximum does not depend on the order).
  const double largest = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, basis.sensorCount(), 1024), 0.0,
      [&](const tbb::blocked_range<int>& range, double running) {
        for (int k = range.begin(); k != range.end(); ++k) {
          running = std::max(running, squaredSensorMove(linearization, step, dimension, k));
        }
        return running;
      },
      [](double a, double b) { return std::max(a, b); });
  return std::sqrt(largest);
}

/// q / (1 - q) for the ratio q = change / previous of two successive changes, at least 1 and at
/// most kMaximumRemainingFactor (also when there is no previous change or q >= 1).
constexpr double kMaximumRemainingFactor = 100.0;
double remainingFactor(double change, double previous) {
  if (!(previous > 0.0)) return change > 0.0 ? kMaximumRemainingFactor : 1.0;
  const double q = change / previous;
  if (q >= 1.0 - 1.0 / (kMaximumRemainingFactor + 1.0)) return kMaximumRemainingFactor;
  return std::clamp(q / (1.0 - q), 1.0, kMaximumRemainingFactor);
}

std::string number(double value) {
  std::ostringstream text;
  text.precision(3);
  text << value;
  return text.str();
}

}  // namespace

FitLoopResult runFitLoop(const std::vector<Eigen::Vector3d>& initial,
                         const FitLoopSettings& settings, FitProblem& problem) {
  const int n = static_cast<int>(initial.size());
  validate(settings, n);
  const int d = settings.dimension;
  const bool automatic = settings.bendingWeight < 0.0 && settings.bending.nonZeros() > 0;
  QuadraticModel model(n, d, settings.fixedSmoothing, settings.bending);
  AutomaticBending bending(automatic ? kInitialAutomaticBending
                                     : std::max(0.0, settings.bendingWeight));
  model.setSmoothingScale(bending.weight());
  if (settings.stepSmoothness > 0.0 && settings.stepRegularizer.nonZeros() > 0) {
    model.setStepRegularizer(settings.stepRegularizer, settings.stepSmoothness);
  }

  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& point : initial) box.extend(point);
  const double size = box.sizes().maxCoeff();
  const double resolvedMove = kResolvedFraction * problem.resolution();

  FitLoopResult result;
  std::vector<Eigen::Vector3d> points = initial;
  DataError error = problem.measure(points);
  if (!error.valid) {
    throw InputError("the initial " + settings.splineName +
                     " is not inside the region where the target answers");
  }
  problem.accept();
  double objective = objectiveOf(error, model.smoothingEnergy(points));
  result.history.push_back({0, objective, rmsOf(error), std::sqrt(error.maxSquared), 0.0, 0.0, 0.0,
                            0.0, bending.weight(), 0.0});
  if (settings.keepIterates) result.iterates.push_back(points);

  // The geometric tolerance of a move for a fit of RMS `rms` over `count` terms.
  const auto moveTolerance = [&](double rms, int count) {
    return std::max({settings.stepTolerance * size,
                     settings.moveTolerance * fitResolution(rms, n, count), resolvedMove});
  };

  double damping = settings.levenbergMarquardt ? settings.initialDamping : 0.0;
  double formShare = 1.0;  // share of the plain forms; 1 - formShare of the second-order terms
  double radius = std::numeric_limits<double>::infinity();  // trust radius of second-order steps
  FitLinearization linearization;
  // The correction's model (same smoothing), made when the problem offers corrections.
  std::optional<QuadraticModel> correctionModel;
  FitLinearization correctionLinearization;
  if (problem.offersCorrection()) {
    correctionModel.emplace(n, d, settings.fixedSmoothing, settings.bending);
  }
  bool stopped = false;
  double lastMove = 0.0;
  double previousSensorMove = -1.0;
  double previousRmsChange = -1.0;
  for (int iteration = 1; iteration <= settings.maxIterations && !stopped; ++iteration) {
    if (settings.progress) {
      settings.progress("fit", static_cast<double>(iteration - 1) / settings.maxIterations);
    }
    problem.linearize(points, linearization);
    if (linearization.basis == nullptr ||
        static_cast<int>(linearization.forms.size()) != linearization.basis->sensorCount()) {
      throw InputError("the fitting problem's linearisation does not match its sensors");
    }
    const bool secondOrder = !linearization.secondOrder.empty();
    const int count = static_cast<int>(linearization.forms.size());
    model.assemble(
        {SensorTerms{linearization.basis, &linearization.forms, count > 0 ? 1.0 / count : 0.0,
                     secondOrder ? &linearization.secondOrder : nullptr}},
        points);
    const double rms = rmsOf(error);
    if (automatic) {
      bending.choose(model, linearization,
                     settings.automaticBias * fitResolution(rms, n, std::max(count, 1)), d);
      objective = objectiveOf(error, model.smoothingEnergy(points));
    }
    const double tolerance = moveTolerance(rms, count);

    // Step control: Levenberg-Marquardt damping (TDM); a trust-region choice of the second-order
    // share (SDM II) that falls back to the plain forms and a line search; or the line search on
    // the true objective alone.
    bool accepted = false;
    bool flat = false;  // the objective at the first full step equals E to rounding
    double firstStep = -1.0;
    double scale = 1.0;
    double usedDamping = damping;
    double usedShare = formShare;
    DataError acceptedError;
    double acceptedObjective = objective;
    std::vector<Eigen::Vector3d> acceptedPoints;
    bool correctedGain = false;  // the accepted candidate was lowered by its correction
    // The candidate points + s step, measured, then corrected (FitProblem::correction()) when the
    // problem offers a correction: the problem's last measurement is the returned points'.
    struct Trial {
      std::vector<Eigen::Vector3d> points;
      DataError error;
      double value = 0.0;             // E of the (corrected) candidate
      double uncorrectedValue = 0.0;  // E of points + s step itself
    };
    const auto evaluate = [&](const std::vector<Eigen::Vector3d>& step, double s) {
      Trial trial;
      trial.points = moved(points, step, s);
      trial.error = problem.measure(trial.points);
      trial.value = objectiveOf(trial.error, model.smoothingEnergy(trial.points));
      trial.uncorrectedValue = trial.value;
      if (correctionModel && trial.error.valid && formShare < 1.0 &&
          problem.correction(trial.points, correctionLinearization)) {
        const int terms = static_cast<int>(correctionLinearization.forms.size());
        correctionModel->assemble(
            {SensorTerms{correctionLinearization.basis, &correctionLinearization.forms,
                         terms > 0 ? 1.0 / terms : 0.0, nullptr}},
            trial.points);
        correctionModel->setSmoothingScale(bending.weight());
        std::vector<Eigen::Vector3d> correctedPoints =
            moved(trial.points, correctionModel->solveAssembled(1.0, 0.0), 1.0);
        const DataError correctedError = problem.measure(correctedPoints);
        const double correctedValue =
            objectiveOf(correctedError, model.smoothingEnergy(correctedPoints));
        if (correctedValue <= trial.value) {
          trial.points = std::move(correctedPoints);
          trial.error = correctedError;
          trial.value = correctedValue;
        } else {
          problem.measure(trial.points);  // rounding: keep the uncorrected candidate
        }
      }
      return trial;
    };
    // Measures the candidate points + s step for s = 1, 1/2, ... (`halvings` tries) and accepts
    // the first that lowers E. Returns the actual decrease of the full (corrected) step.
    const auto lineSearch = [&](const std::vector<Eigen::Vector3d>& step, int halvings) {
      double fullDecrease = -std::numeric_limits<double>::infinity();
      scale = 1.0;
      correctedGain = false;
      for (int h = 0; h < halvings; ++h, scale *= 0.5) {
        Trial trial = evaluate(step, scale);
        if (h == 0) {
          fullDecrease = objective - trial.value;
          if (firstStep < 0.0) {
            firstStep = largestSensorMove(linearization, step, d);
            flat = std::abs(trial.value - objective) <= 1e-12 * objective;
          }
        }
        if (trial.value < objective) {
          accepted = true;
          correctedGain = trial.value < trial.uncorrectedValue;
          acceptedError = trial.error;
          acceptedObjective = trial.value;
          acceptedPoints = std::move(trial.points);
          return fullDecrease;
        }
        if (largestMove(step) * scale < 1e-3 * tolerance) break;
      }
      return fullDecrease;
    };
    // After a full step whose correction gained much more than the model predicted (the step
    // follows a curved valley that the correction straightens): tries 2, 4, ... times the step,
    // each corrected, while E keeps falling, and keeps the best.
    const auto extrapolate = [&](const std::vector<Eigen::Vector3d>& step, double predicted) {
      if (!correctionModel || !correctedGain || scale != 1.0) return;
      const double gain = objective - acceptedObjective;
      if (!(gain > kExtrapolationGain * std::max(predicted, 0.0))) return;
      bool lastIsAccepted = true;
      for (double s = 2.0; s <= kLargestExtrapolation; s *= 2.0) {
        Trial trial = evaluate(step, s);
        lastIsAccepted = trial.value < acceptedObjective;
        if (!lastIsAccepted) break;
        scale = s;
        acceptedError = trial.error;
        acceptedObjective = trial.value;
        acceptedPoints = std::move(trial.points);
      }
      if (!lastIsAccepted) problem.measure(acceptedPoints);  // accept() takes the last measured
    };

    if (settings.levenbergMarquardt) {
      for (int attempt = 0; attempt < 12 && !accepted; ++attempt) {
        const std::vector<Eigen::Vector3d> step = model.solveAssembled(1.0, damping);
        usedDamping = damping;
        lineSearch(step, 1);
        if (!accepted) damping = std::max(10.0 * damping, 1e-6);
      }
      if (accepted) damping = std::max(damping / 3.0, 1e-9);
    } else if (secondOrder) {
      int failures = 0;
      for (int attempt = 0; attempt < 10 && !accepted; ++attempt) {
        // With second-order terms (share < 1) only a positive definite model gives a step.
        std::optional<std::vector<Eigen::Vector3d>> solved =
            formShare < 1.0 ? model.minimizeAssembled(1.0 - formShare, 0.0)
                            : model.solveAssembled(0.0, 0.0);
        if (!solved) {
          formShare = moreForms(formShare);
          continue;
        }
        std::vector<Eigen::Vector3d> step = std::move(*solved);
        usedShare = formShare;
        double length = largestMove(step);
        const bool truncated = formShare < 1.0 && length > radius;
        if (truncated) {
          for (Eigen::Vector3d& c : step) c *= radius / length;
          length = radius;
        }
        const double predicted = model.predictedDecrease(step);
        const double actual = lineSearch(step, formShare == 1.0 ? 30 : 1);
        const double ratio = predicted > 0.0 ? actual / predicted : 0.0;
        if (accepted) extrapolate(step, predicted);

        if (accepted) {
          if (scale >= 1.0 && ratio > 0.75) radius = std::max(radius, 2.0 * length);
          if (scale >= 1.0 && ratio > 0.5) {
            formShare = fewerForms(formShare);
          } else if (ratio < 0.25) {
            formShare = moreForms(formShare);
          }
        } else if (formShare < 1.0) {
          radius = 0.5 * length;
          if (++failures >= 2) {
            formShare = moreForms(formShare);
            failures = 0;
          }
        } else {
          break;
        }
      }
    } else {
      lineSearch(model.solveAssembled(1.0, 0.0), 30);
    }

    if (!accepted) {
      if (firstStep >= 0.0 && (firstStep <= tolerance || flat)) {
        result.status = FitStatus::Converged;
        result.reason = firstStep <= resolvedMove && resolvedMove > 0.0
                            ? "the model's step (" + number(firstStep) + ") is below " +
                                  number(kResolvedFraction) + " of the target's resolution (" +
                                  number(problem.resolution()) +
                                  "): the target resolves no further improvement"
                            : "the objective no longer decreases and the model's step (" +
                                  number(firstStep) + ") is within the geometric tolerance (" +
                                  number(tolerance) + ") or changes it only by rounding";
      } else {
        result.status = FitStatus::Stalled;
        result.reason =
            "no step along the solution of the quadratic model lowered the objective (the model's "
            "step moves the sensors by up to " +
            number(std::max(firstStep, 0.0)) + " across the target; geometric tolerance " +
            number(tolerance) + ")";
      }
      stopped = true;
      break;
    }
    problem.accept();
    const std::vector<Eigen::Vector3d> acceptedStep = moved(acceptedPoints, points, -1.0);
    const double stepLength = largestMove(acceptedStep);
    // The move that decides convergence: the accepted step's, or the model's full step when the
    // line search had to cut it (a cut step says nothing about being near the solution).
    const double sensorMove =
        std::max(largestSensorMove(linearization, acceptedStep, d), std::max(firstStep, 0.0));
    const double relativeDecrease = (objective - acceptedObjective) / objective;
    points = std::move(acceptedPoints);
    objective = acceptedObjective;
    error = acceptedError;
    const double newRms = rmsOf(error);
    result.history.push_back({iteration, objective, newRms, std::sqrt(error.maxSquared), stepLength,
                              sensorMove, scale, settings.levenbergMarquardt ? usedDamping : 0.0,
                              bending.weight(), secondOrder ? 1.0 - usedShare : 0.0});
    if (settings.keepIterates) result.iterates.push_back(points);
    lastMove = sensorMove;

    const double newTolerance = moveTolerance(newRms, error.count);
    const double rmsChange = std::abs(newRms - rms);
    // What is left to move if the iteration keeps converging at its latest rate q: the last
    // change times q / (1 - q) (at least the last change itself).
    const double remainingMove = sensorMove * remainingFactor(sensorMove, previousSensorMove);
    const double remainingRms = rmsChange * remainingFactor(rmsChange, previousRmsChange);
    previousSensorMove = sensorMove;
    previousRmsChange = rmsChange;
    if (remainingMove <= newTolerance && remainingRms <= newTolerance) {
      result.status = FitStatus::Converged;
      result.reason = "the " + settings.splineName +
                      " stopped moving: the sensors' last move across the target (" +
                      number(sensorMove) + ") and RMS change (" + number(rmsChange) +
                      "), extrapolated at their rate of convergence, are within the geometric "
                      "tolerance " +
                      number(newTolerance) + " (largest control-point move " + number(stepLength) +
                      ")";
      stopped = true;
    } else if (settings.distanceTolerance > 0.0 && newRms <= settings.distanceTolerance) {
      result.status = FitStatus::Converged;
      result.reason = "the RMS distance reached the distance tolerance";
      stopped = true;
    } else if (settings.objectiveTolerance > 0.0 &&
               relativeDecrease < settings.objectiveTolerance) {
      result.status = FitStatus::Converged;
      result.reason = "the objective decreased by less than the objective tolerance";
      stopped = true;
    }
    if (!stopped && settings.interrupt && settings.interrupt(iteration, points)) {
      result.interrupted = true;
      result.status = FitStatus::IterationCap;
      result.reason = "interrupted after iteration " + std::to_string(iteration);
      stopped = true;
    }
  }
  if (!stopped) {
    result.status = FitStatus::IterationCap;
    result.reason = "reached the iteration cap of " + std::to_string(settings.maxIterations) +
                    " while the " + settings.splineName +
                    " was still moving (last move across the target " + number(lastMove) +
                    ", tolerance " + number(moveTolerance(rmsOf(error), error.count)) + ")";
  }
  result.controlPoints = std::move(points);
  if (settings.progress) settings.progress("fit", 1.0);
  return result;
}

}  // namespace detail
}  // namespace d2vdb
