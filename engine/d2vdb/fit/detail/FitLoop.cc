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

/// Fraction of the target's resolved length (a field's voxel) below which a move is not resolved:
/// the approximants' own error (footpoints to a few hundredths of a voxel, piecewise per voxel)
/// makes the objective rough on that scale.
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

/// The statistical precision of a least-squares fit with `controlPoints` points' worth of
/// freedom to `count` squared distances of RMS `rms`.
double fitPrecision(double rms, int controlPoints, int count) {
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

/// A candidate net, points + s step, measured and, when the problem offers one, corrected
/// (FitProblem::correction()): the problem's last measurement is the candidate's.
struct Trial {
  std::vector<Eigen::Vector3d> points;
  DataError error;
  double value = 0.0;             ///< E of the (corrected) candidate
  double uncorrectedValue = 0.0;  ///< E of points + s step itself
};

/// What one iteration's step control found.
struct StepResult {
  bool accepted = false;
  bool flat = false;           ///< the objective at the first full step equals E to rounding
  double firstStep = -1.0;     ///< the first full step's largest sensor move (-1: none measured)
  double scale = 1.0;          ///< the accepted multiple of the step
  double damping = 0.0;        ///< the Levenberg-Marquardt damping of the accepted step
  double formShare = 1.0;      ///< the plain forms' share in the accepted step's model
  bool correctedGain = false;  ///< the accepted candidate was lowered by its correction
  DataError error;             ///< the accepted candidate's
  double objective = 0.0;      ///< the accepted candidate's E (the current E until one is)
  std::vector<Eigen::Vector3d> points;
};

/// The state of runFitLoop between and within its iterations.
class FitLoop {
 public:
  FitLoop(const std::vector<Eigen::Vector3d>& initial, const FitLoopSettings& settings,
          FitProblem& problem)
      : settings_(settings),
        problem_(problem),
        n_(validatedCount(settings, initial)),
        d_(settings.dimension),
        automatic_(settings.bendingWeight < 0.0 && settings.bending.nonZeros() > 0),
        model_(n_, d_, settings.fixedSmoothing, settings.bending),
        bending_(automatic_ ? kInitialAutomaticBending : std::max(0.0, settings.bendingWeight)),
        points_(initial) {
    model_.setSmoothingScale(bending_.weight());
    if (settings.stepSmoothness > 0.0 && settings.stepRegularizer.nonZeros() > 0) {
      model_.setStepRegularizer(settings.stepRegularizer, settings.stepSmoothness);
    }
    Eigen::AlignedBox3d box;
    for (const Eigen::Vector3d& point : initial) box.extend(point);
    size_ = box.sizes().maxCoeff();
    resolvedMove_ = kResolvedFraction * problem.resolvedLength();
  }

  FitLoopResult run() {
    start();
    bool stopped = false;
    for (int iteration = 1; iteration <= settings_.maxIterations && !stopped; ++iteration) {
      stopped = iterate(iteration);
    }
    if (!stopped) {
      result_.status = FitStatus::IterationCap;
      result_.reason = "reached the iteration cap of " + std::to_string(settings_.maxIterations) +
                       " while the " + settings_.splineName +
                       " was still moving (last move across the target " + number(lastMove_) +
                       ", tolerance " + number(moveTolerance(rmsOf(error_), error_.count)) + ")";
    }
    result_.controlPoints = std::move(points_);
    if (settings_.progress) settings_.progress("fit", 1.0);
    return std::move(result_);
  }

 private:
  static int validatedCount(const FitLoopSettings& settings,
                            const std::vector<Eigen::Vector3d>& initial) {
    const int n = static_cast<int>(initial.size());
    validate(settings, n);
    return n;
  }

  /// Measures the initial net (history row 0).
  void start() {
    error_ = problem_.measure(points_);
    if (!error_.valid) {
      throw InputError("the initial " + settings_.splineName +
                       " is not inside the region where the target answers");
    }
    problem_.accept();
    objective_ = objectiveOf(error_, model_.smoothingEnergy(points_));
    result_.history.push_back({0, objective_, rmsOf(error_), std::sqrt(error_.maxSquared), 0.0, 0.0,
                               0.0, 0.0, bending_.weight(), 0.0});
    if (settings_.keepIterates) result_.iterates.push_back(points_);
    // The correction's model (same smoothing), made when the problem offers corrections.
    if (problem_.offersCorrection()) {
      correctionModel_.emplace(n_, d_, settings_.fixedSmoothing, settings_.bending);
    }
  }

  /// The geometric tolerance of a move for a fit of RMS `rms` over `count` terms.
  double moveTolerance(double rms, int count) const {
    return std::max({settings_.stepTolerance * size_,
                     settings_.moveTolerance * fitPrecision(rms, n_, count), resolvedMove_});
  }

  /// One iteration; true when the loop stops after it.
  bool iterate(int iteration) {
    if (settings_.progress) {
      settings_.progress("fit", static_cast<double>(iteration - 1) / settings_.maxIterations);
    }
    linearize();
    step_ = StepResult{};
    step_.damping = damping_;
    step_.formShare = formShare_;
    step_.objective = objective_;
    // Step control: Levenberg-Marquardt damping (TDM); a trust-region choice of the second-order
    // share (SDM II) that falls back to the plain forms and a line search; or the line search on
    // the true objective alone.
    if (settings_.levenbergMarquardt) {
      dampedStep();
    } else if (secondOrder_) {
      trustRegionStep();
    } else {
      lineSearch(model_.solveAssembled(1.0, 0.0), 30);
    }
    if (!step_.accepted) {
      stopWithoutStep();
      return true;
    }
    return acceptStep(iteration);
  }

  /// Linearises the problem at the current net, assembles the model and chooses the automatic
  /// bending weight.
  void linearize() {
    problem_.linearize(points_, linearization_);
    if (linearization_.basis == nullptr ||
        static_cast<int>(linearization_.forms.size()) != linearization_.basis->sensorCount()) {
      throw InputError("the fitting problem's linearisation does not match its sensors");
    }
    secondOrder_ = !linearization_.secondOrder.empty();
    const int count = static_cast<int>(linearization_.forms.size());
    model_.assemble(
        {SensorTerms{linearization_.basis, &linearization_.forms, count > 0 ? 1.0 / count : 0.0,
                     secondOrder_ ? &linearization_.secondOrder : nullptr}},
        points_);
    rms_ = rmsOf(error_);
    if (automatic_) {
      bending_.choose(model_, linearization_,
                      settings_.automaticBias * fitPrecision(rms_, n_, std::max(count, 1)), d_);
      objective_ = objectiveOf(error_, model_.smoothingEnergy(points_));
    }
    tolerance_ = moveTolerance(rms_, count);
  }

  /// The candidate points + s step (Trial).
  Trial evaluate(const std::vector<Eigen::Vector3d>& step, double s) {
    Trial trial;
    trial.points = moved(points_, step, s);
    trial.error = problem_.measure(trial.points);
    trial.value = objectiveOf(trial.error, model_.smoothingEnergy(trial.points));
    trial.uncorrectedValue = trial.value;
    if (correctionModel_ && trial.error.valid && formShare_ < 1.0 &&
        problem_.correction(trial.points, correctionLinearization_)) {
      const int terms = static_cast<int>(correctionLinearization_.forms.size());
      correctionModel_->assemble(
          {SensorTerms{correctionLinearization_.basis, &correctionLinearization_.forms,
                       terms > 0 ? 1.0 / terms : 0.0, nullptr}},
          trial.points);
      correctionModel_->setSmoothingScale(bending_.weight());
      std::vector<Eigen::Vector3d> correctedPoints =
          moved(trial.points, correctionModel_->solveAssembled(1.0, 0.0), 1.0);
      const DataError correctedError = problem_.measure(correctedPoints);
      const double correctedValue =
          objectiveOf(correctedError, model_.smoothingEnergy(correctedPoints));
      if (correctedValue <= trial.value) {
        trial.points = std::move(correctedPoints);
        trial.error = correctedError;
        trial.value = correctedValue;
      } else {
        problem_.measure(trial.points);  // rounding: keep the uncorrected candidate
      }
    }
    return trial;
  }

  /// Takes `trial` as the accepted candidate of the step.
  void take(Trial& trial) {
    step_.error = trial.error;
    step_.objective = trial.value;
    step_.points = std::move(trial.points);
  }

  /// Measures the candidate points + s step for s = 1, 1/2, ... (`halvings` tries) and accepts
  /// the first that lowers E. Returns the actual decrease of the full (corrected) step.
  double lineSearch(const std::vector<Eigen::Vector3d>& step, int halvings) {
    double fullDecrease = -std::numeric_limits<double>::infinity();
    step_.scale = 1.0;
    step_.correctedGain = false;
    for (int h = 0; h < halvings; ++h, step_.scale *= 0.5) {
      Trial trial = evaluate(step, step_.scale);
      if (h == 0) {
        fullDecrease = objective_ - trial.value;
        if (step_.firstStep < 0.0) {
          step_.firstStep = largestSensorMove(linearization_, step, d_);
          step_.flat = std::abs(trial.value - objective_) <= 1e-12 * objective_;
        }
      }
      if (trial.value < objective_) {
        step_.accepted = true;
        step_.correctedGain = trial.value < trial.uncorrectedValue;
        take(trial);
        return fullDecrease;
      }
      if (largestMove(step) * step_.scale < 1e-3 * tolerance_) break;
    }
    return fullDecrease;
  }

  /// After a full step whose correction gained much more than the model predicted (the step
  /// follows a curved valley that the correction straightens): tries 2, 4, ... times the step,
  /// each corrected, while E keeps falling, and keeps the best.
  void extrapolate(const std::vector<Eigen::Vector3d>& step, double predicted) {
    if (!correctionModel_ || !step_.correctedGain || step_.scale != 1.0) return;
    const double gain = objective_ - step_.objective;
    if (!(gain > kExtrapolationGain * std::max(predicted, 0.0))) return;
    bool lastIsAccepted = true;
    for (double s = 2.0; s <= kLargestExtrapolation; s *= 2.0) {
      Trial trial = evaluate(step, s);
      lastIsAccepted = trial.value < step_.objective;
      if (!lastIsAccepted) break;
      step_.scale = s;
      take(trial);
    }
    if (!lastIsAccepted) problem_.measure(step_.points);  // accept() takes the last measured
  }

  /// Levenberg-Marquardt: the damping rises tenfold until a full step lowers E, and falls by a
  /// third after one does.
  void dampedStep() {
    for (int attempt = 0; attempt < 12 && !step_.accepted; ++attempt) {
      const std::vector<Eigen::Vector3d> step = model_.solveAssembled(1.0, damping_);
      step_.damping = damping_;
      lineSearch(step, 1);
      if (!step_.accepted) damping_ = std::max(10.0 * damping_, 1e-6);
    }
    if (step_.accepted) damping_ = std::max(damping_ / 3.0, 1e-9);
  }

  /// Second-order terms: the trust-region choice of the forms' share and radius (runFitLoop).
  void trustRegionStep() {
    int failures = 0;
    for (int attempt = 0; attempt < 10 && !step_.accepted; ++attempt) {
      // With second-order terms (share < 1) only a positive definite model gives a step.
      std::optional<std::vector<Eigen::Vector3d>> solved =
          formShare_ < 1.0 ? model_.minimizeAssembled(1.0 - formShare_, 0.0)
                           : model_.solveAssembled(0.0, 0.0);
      if (!solved) {
        formShare_ = moreForms(formShare_);
        continue;
      }
      std::vector<Eigen::Vector3d> step = std::move(*solved);
      step_.formShare = formShare_;
      double length = largestMove(step);
      const bool truncated = formShare_ < 1.0 && length > radius_;
      if (truncated) {
        for (Eigen::Vector3d& c : step) c *= radius_ / length;
        length = radius_;
      }
      const double predicted = model_.predictedDecrease(step);
      const double actual = lineSearch(step, formShare_ == 1.0 ? 30 : 1);
      const double ratio = predicted > 0.0 ? actual / predicted : 0.0;
      if (step_.accepted) extrapolate(step, predicted);

      if (step_.accepted) {
        if (step_.scale >= 1.0 && ratio > 0.75) radius_ = std::max(radius_, 2.0 * length);
        if (step_.scale >= 1.0 && ratio > 0.5) {
          formShare_ = fewerForms(formShare_);
        } else if (ratio < 0.25) {
          formShare_ = moreForms(formShare_);
        }
      } else if (formShare_ < 1.0) {
        radius_ = 0.5 * length;
        if (++failures >= 2) {
          formShare_ = moreForms(formShare_);
          failures = 0;
        }
      } else {
        break;
      }
    }
  }

  /// No step lowered E: converged when the model's step is within the tolerance (or changes E
  /// only by rounding), else stalled.
  void stopWithoutStep() {
    const double firstStep = step_.firstStep;
    if (firstStep >= 0.0 && (firstStep <= tolerance_ || step_.flat)) {
      result_.status = FitStatus::Converged;
      result_.reason = firstStep <= resolvedMove_ && resolvedMove_ > 0.0
                           ? "the model's step (" + number(firstStep) + ") is below " +
                                 number(kResolvedFraction) + " of the target's resolved length (" +
                                 number(problem_.resolvedLength()) +
                                 "): the target resolves no further improvement"
                           : "the objective no longer decreases and the model's step (" +
                                 number(firstStep) + ") is within the geometric tolerance (" +
                                 number(tolerance_) + ") or changes it only by rounding";
    } else {
      result_.status = FitStatus::Stalled;
      result_.reason =
          "no step along the solution of the quadratic model lowered the objective (the model's "
          "step moves the sensors by up to " +
          number(std::max(firstStep, 0.0)) + " across the target; geometric tolerance " +
          number(tolerance_) + ")";
    }
  }

  /// Makes the accepted candidate the current net and records it; true when the loop stops.
  bool acceptStep(int iteration) {
    problem_.accept();
    const std::vector<Eigen::Vector3d> acceptedStep = moved(step_.points, points_, -1.0);
    const double stepLength = largestMove(acceptedStep);
    // The move that decides convergence: the accepted step's, or the model's full step when the
    // line search had to cut it (a cut step says nothing about being near the solution).
    const double sensorMove = std::max(largestSensorMove(linearization_, acceptedStep, d_),
                                       std::max(step_.firstStep, 0.0));
    const double relativeDecrease = (objective_ - step_.objective) / objective_;
    points_ = std::move(step_.points);
    objective_ = step_.objective;
    error_ = step_.error;
    const double newRms = rmsOf(error_);
    result_.history.push_back({iteration, objective_, newRms, std::sqrt(error_.maxSquared),
                               stepLength, sensorMove, step_.scale,
                               settings_.levenbergMarquardt ? step_.damping : 0.0,
                               bending_.weight(), secondOrder_ ? 1.0 - step_.formShare : 0.0});
    if (settings_.keepIterates) result_.iterates.push_back(points_);
    lastMove_ = sensorMove;
    if (converged(sensorMove, newRms, stepLength, relativeDecrease)) return true;
    if (settings_.interrupt && settings_.interrupt(iteration, points_)) {
      result_.interrupted = true;
      result_.status = FitStatus::IterationCap;
      result_.reason = "interrupted after iteration " + std::to_string(iteration);
      return true;
    }
    return false;
  }

  /// The stopping tests after an accepted step (runFitLoop); sets the status and reason when one
  /// holds.
  bool converged(double sensorMove, double newRms, double stepLength, double relativeDecrease) {
    const double newTolerance = moveTolerance(newRms, error_.count);
    const double rmsChange = std::abs(newRms - rms_);
    // What is left to move if the iteration keeps converging at its latest rate q: the last
    // change times q / (1 - q) (at least the last change itself).
    const double remainingMove = sensorMove * remainingFactor(sensorMove, previousSensorMove_);
    const double remainingRms = rmsChange * remainingFactor(rmsChange, previousRmsChange_);
    previousSensorMove_ = sensorMove;
    previousRmsChange_ = rmsChange;
    if (remainingMove <= newTolerance && remainingRms <= newTolerance) {
      result_.status = FitStatus::Converged;
      result_.reason = "the " + settings_.splineName +
                       " stopped moving: the sensors' last move across the target (" +
                       number(sensorMove) + ") and RMS change (" + number(rmsChange) +
                       "), extrapolated at their rate of convergence, are within the geometric "
                       "tolerance " +
                       number(newTolerance) + " (largest control-point move " + number(stepLength) +
                       ")";
      return true;
    }
    if (settings_.distanceTolerance > 0.0 && newRms <= settings_.distanceTolerance) {
      result_.status = FitStatus::Converged;
      result_.reason = "the RMS distance reached the distance tolerance";
      return true;
    }
    if (settings_.objectiveTolerance > 0.0 && relativeDecrease < settings_.objectiveTolerance) {
      result_.status = FitStatus::Converged;
      result_.reason = "the objective decreased by less than the objective tolerance";
      return true;
    }
    return false;
  }

  const FitLoopSettings& settings_;
  FitProblem& problem_;
  const int n_;           ///< control points
  const int d_;           ///< dimension
  const bool automatic_;  ///< automatic bending weight
  QuadraticModel model_;
  AutomaticBending bending_;
  std::vector<Eigen::Vector3d> points_;  ///< the current net
  double size_ = 0.0;                    ///< the largest side of the initial net's bounding box
  double resolvedMove_ = 0.0;            ///< the smallest move the target resolves
  FitLoopResult result_;
  DataError error_;         ///< the current net's
  double objective_ = 0.0;  ///< E of the current net
  double damping_ = settings_.levenbergMarquardt ? settings_.initialDamping : 0.0;
  double formShare_ = 1.0;  ///< share of the plain forms; 1 - formShare_ of the second order
  double radius_ = std::numeric_limits<double>::infinity();  ///< trust radius (second order)
  FitLinearization linearization_;
  std::optional<QuadraticModel> correctionModel_;  ///< with problem_.offersCorrection()
  FitLinearization correctionLinearization_;
  double lastMove_ = 0.0;
  double previousSensorMove_ = -1.0;
  double previousRmsChange_ = -1.0;
  // The current iteration: its linearisation has second-order terms, the RMS distance and move
  // tolerance at its start, its step.
  bool secondOrder_ = false;
  double rms_ = 0.0;
  double tolerance_ = 0.0;
  StepResult step_;
};

}  // namespace

FitLoopResult runFitLoop(const std::vector<Eigen::Vector3d>& initial,
                         const FitLoopSettings& settings, FitProblem& problem) {
  return FitLoop(initial, settings, problem).run();
}

}  // namespace detail
}  // namespace d2vdb
