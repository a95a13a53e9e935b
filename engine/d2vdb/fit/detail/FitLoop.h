// Internal: the iteration shared by the squared-distance fitters. It knows nothing about curves or
// surfaces: a control net is a list of points, sensors are fixed linear maps from it
// (SensorMap), the target contributes one quadratic form per sensor (plus optional rank-one
// second-order terms), and smoothing is a matrix over the control points. Not part of the
// public API.
#pragma once

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <functional>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/Approximant.h"
#include "d2vdb/fit/FitHistory.h"
#include "d2vdb/fit/detail/QuadraticModel.h"
#include "d2vdb/fit/detail/SensorMap.h"

namespace d2vdb::detail {

/// The true data error of a control net: sum and maximum of the squared distances over `count`
/// terms. valid = false when the net left the region where the target answers.
struct DataError {
  double sum = 0.0;
  double maxSquared = 0.0;
  int count = 0;
  bool valid = true;
};

/// A fitter's model of its data term at one control net. The loop uses the mean of the forms
/// (weight 1 / forms.size() each) plus `secondOrder` times a blend weight in [0, 1] that its
/// step control chooses.
struct FitLinearization {
  /// The sensors: fixed linear maps from the control points (owned by the problem, valid until
  /// its next linearize()).
  const SensorMap* basis = nullptr;
  /// One quadratic form per sensor (world units), positive semidefinite: SDM, TDM, PDM, ...
  std::vector<QuadraticForm> forms;
  /// Optional exact second-order terms the forms leave out (e.g. the footpoint parameter's
  /// dependence on the control points in SDM II): with them the model is Newton's, possibly
  /// indefinite. Empty = none; the loop then always uses the forms alone.
  RankOneTerms secondOrder;
};

/// What a fitter supplies to the loop.
class FitProblem {
 public:
  virtual ~FitProblem() = default;
  /// The model of the data term at `controlPoints` (the loop's current net).
  virtual void linearize(const std::vector<Eigen::Vector3d>& controlPoints,
                         FitLinearization& linearization) = 0;
  /// The true data error of a candidate net (remembers what it needs for accept()). Its count
  /// must equal the number of forms of the linearisation of an accepted net.
  virtual DataError measure(const std::vector<Eigen::Vector3d>& controlPoints) = 0;
  /// The last measured candidate became the current net.
  virtual void accept() {}
  /// Whether correction() may return true (the loop then keeps a second model for it).
  virtual bool offersCorrection() const { return false; }
  /// A correction of the candidate `controlPoints`, the net measure() was last called with (a
  /// second-order correction in the trust-region sense): quadratic forms over the sensors of
  /// `correction.basis` whose mean is, for every net, at least the data term, and equals it at
  /// `controlPoints` (e.g. the squared distances to footpoints held fixed). The loop replaces
  /// the candidate by the minimiser of that mean plus the smoothing, which therefore never
  /// raises the objective. false = no correction (the default).
  virtual bool correction(const std::vector<Eigen::Vector3d>& /*controlPoints*/,
                          FitLinearization& /*correction*/) {
    return false;
  }
  /// The target's resolved length (SquaredDistanceTarget::resolvedLength()); 0 for exact data.
  virtual double resolvedLength() const { return 0.0; }
};

/// The loop's parameters. Weights are dimensionless, distances world units.
struct FitLoopSettings {
  int dimension = 3;                 ///< 2 (z stays 0) or 3
  std::string splineName = "curve";  ///< what the net describes, for messages
  /// Unit-weight bending matrix over the control points (e.g. the Gram matrix of the second
  /// derivatives, or a surface's thin-plate energy); empty = no bending term.
  Eigen::SparseMatrix<double> bending;
  /// Its weight lambda2 >= 0, or negative for automatic (see runFitLoop).
  double bendingWeight = -1.0;
  /// Further smoothing with its weight already applied (e.g. stretch); empty = none.
  Eigen::SparseMatrix<double> fixedSmoothing;
  /// Step regulariser matrix and its relative weight (QuadraticModel::setStepRegularizer).
  Eigen::SparseMatrix<double> stepRegularizer;
  double stepSmoothness = 0.0;
  /// Levenberg-Marquardt damping instead of a line search (TDM), with its initial value.
  bool levenbergMarquardt = false;
  double initialDamping = 1e-3;
  /// Automatic bending weight: the bias it causes is kept at this fraction of the fit's
  /// resolution (see runFitLoop).
  double automaticBias = 0.25;
  int maxIterations = 100;
  double distanceTolerance = 0.0;   ///< converged when the RMS distance falls to this (0 = off)
  double stepTolerance = 1e-9;      ///< move tolerance as a fraction of the net's size
  double moveTolerance = 0.1;       ///< move tolerance as a fraction of the fit's precision
  double objectiveTolerance = 0.0;  ///< converged when E falls by less than this fraction (0 = off)
  bool keepIterates = false;
  ProgressCallback progress;  ///< stage "fit", fraction = iteration / maxIterations
  /// Called after every iteration that did not stop the fit, with its number and the net; true
  /// ends the loop there (FitLoopResult::interrupted). Empty = never.
  std::function<bool(int iteration, const std::vector<Eigen::Vector3d>& controlPoints)> interrupt;
};

/// The loop's outcome.
struct FitLoopResult {
  std::vector<Eigen::Vector3d> controlPoints;
  FitStatus status = FitStatus::IterationCap;
  std::string reason;
  std::vector<FitIteration> history;  ///< row 0 = initial net, then one row per iteration
  std::vector<std::vector<Eigen::Vector3d>> iterates;  ///< with keepIterates: initial, then all
  bool interrupted = false;  ///< settings.interrupt ended the loop (status IterationCap)
};

/// Runs the fit from `initial` (at least one point; its size is the largest side of its
/// bounding box). Each iteration: linearise, choose the automatic bending weight, solve the
/// quadratic model, control the step on the true objective E = mean squared distance +
/// smoothing, stop on the geometric test.
///
/// Automatic bending (bendingWeight < 0 and a bending matrix): the weight lambda2 is set every
/// iteration so that the shift the bending term causes in the model's minimiser (solved with the
/// plain forms, measured at the sensors in the forms' metric: RMS of sqrt(d^T A d)) equals
/// automaticBias x the fit's precision rms x sqrt(n / N) (rms the RMS distance, n control
/// points, N forms: the statistical uncertainty of a least-squares fit with n points' worth of
/// freedom). Large while the net is far off, it shrinks as the fit converges; its bias stays a
/// fixed fraction of the noise floor.
///
/// Second-order terms (SDM II): the step's model is the forms plus w x the exact second-order
/// terms, w = 1 - s with the forms' share s in {1, 1/4, 1/16, 1/64, 0}: s falls a notch after a
/// full step whose actual decrease was more than half the predicted one, and rises after a poor
/// one (< 1/4), an indefinite system or two failed steps. Steps that use second-order terms are
/// kept within a trust radius (halved after a failure, doubled after a step that went as
/// predicted); with s = 1 the step gets the line search.
///
/// Correction (problems whose offersCorrection()): every candidate of a step that uses the
/// second-order terms (s < 1: the net is already near the target; the plain-form steps that bring
/// it there stay as they are) is replaced by the minimiser of the problem's correction forms plus
/// the smoothing (it can only lower E), and the trust-region rule judges the corrected decrease. A
/// full step whose corrected decrease exceeds twice the model's predicted one is lengthened 2, 4,
/// ... up to 64 times, each corrected, while E keeps falling (the history's step scale is then
/// above 1): the step follows a curved valley that the correction straightens, and near the
/// solution (model and objective agree) the steps stay Newton's.
///
/// Converged when the last iteration's move of the sensors across the target (max_k
/// sqrt(d_k^T A_k d_k) over the sensors' displacements d_k in their forms' metric; the model's
/// full step when the line search cut it) and its change of the RMS distance, each extrapolated
/// at its rate of convergence (times q / (1 - q), q the ratio of the last two, between 1 and 100),
/// are at most max(stepTolerance x size, moveTolerance x rms x sqrt(n / N), target resolved length
/// / 100); when the RMS distance reaches distanceTolerance; when the relative objective decrease
/// falls below objectiveTolerance (if set); or when no step lowers the objective although the
/// model's step is within that tolerance (the objective is flat to rounding, or the target does
/// not resolve the move). Sliding along the target alone does not count as a move.
///
/// InputError for invalid settings, an initial net the target does not answer at, or mismatched
/// matrices. Deterministic for any thread count if the problem is.
FitLoopResult runFitLoop(const std::vector<Eigen::Vector3d>& initial,
                         const FitLoopSettings& settings, FitProblem& problem);

}  // namespace d2vdb::detail
