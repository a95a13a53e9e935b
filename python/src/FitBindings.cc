// d2vdb.fit_curve and d2vdb.fit_surface: the engine's B-spline fitters (PDM, TDM, SDM, TDM+PDM;
// SDM I on fields, curves and surfaces, SDM II on point clouds), placed and run as `d2vdb
// fit-curve` and `d2vdb fit-surface` do.
#include <pybind11/numpy.h>

#include <cmath>

#include "Arrays.h"
#include "Bindings.h"
#include "LongCall.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/fit/CurveFitter.h"
#include "d2vdb/fit/FitMethod.h"
#include "d2vdb/fit/PointCloudFitter.h"
#include "d2vdb/fit/SurfaceFitter.h"
#include "d2vdb/io/FitTarget.h"

namespace d2vdb::python {

namespace {

/// What fit_curve() and fit_surface() return.
struct FitResult {
  py::object spline;  ///< Curve or Surface
  std::string status;
  std::string reason;
  py::dict history;
};

/// The options every fit shares, as keyword arguments (the command's option names).
struct FitKeywords {
  std::string method = "sdm";
  int iterations = 100;
  std::optional<double> smoothness;
  double smoothingBias = 0.25, stepSmoothness = 0, stretch = 0, pdmWeight = 0.01;
  double tolerance = 0, stepTolerance = 1e-9, moveTolerance = 0.1;
  bool exactSecondOrder = true;

  void applyTo(FitOptions& fit) const {
    fit.method = parseFitMethod(method);
    fit.maxIterations = iterations;
    fit.smoothness = smoothness ? *smoothness : -1.0;
    if (smoothness && !(*smoothness >= 0)) throw InputError("smoothness must be None or >= 0");
    fit.automaticSmoothingBias = smoothingBias;
    fit.stepSmoothness = stepSmoothness;
    fit.stretch = stretch;
    fit.pdmWeight = pdmWeight;
    fit.distanceTolerance = tolerance;
    fit.stepTolerance = stepTolerance;
    fit.moveTolerance = moveTolerance;
    fit.exactSecondOrder = exactSecondOrder;
    if (iterations < 0) throw InputError("iterations must be >= 0");
  }
};

FitKeywords keywordsFrom(const py::kwargs& options) {
  FitKeywords keywords;
  for (const auto& [key, value] : options) {
    const std::string name = py::str(key);
    if (name == "method")
      keywords.method = value.cast<std::string>();
    else if (name == "iterations")
      keywords.iterations = value.cast<int>();
    else if (name == "smoothness")
      keywords.smoothness = value.is_none() ? std::optional<double>() : value.cast<double>();
    else if (name == "smoothing_bias")
      keywords.smoothingBias = value.cast<double>();
    else if (name == "step_smoothness")
      keywords.stepSmoothness = value.cast<double>();
    else if (name == "stretch")
      keywords.stretch = value.cast<double>();
    else if (name == "pdm_weight")
      keywords.pdmWeight = value.cast<double>();
    else if (name == "tolerance")
      keywords.tolerance = value.cast<double>();
    else if (name == "step_tolerance")
      keywords.stepTolerance = value.cast<double>();
    else if (name == "move_tolerance")
      keywords.moveTolerance = value.cast<double>();
    else if (name == "exact_second_order")
      keywords.exactSecondOrder = value.cast<bool>();
    else
      throw InputError("unknown fit option '" + name + "'");
  }
  return keywords;
}

py::dict historyArrays(const FitReport& report) {
  const auto rows = static_cast<py::ssize_t>(report.history.size());
  py::array_t<std::int32_t> iteration(rows);
  py::array_t<double> objective(rows), rms(rows), max(rows), step(rows), move(rows), scale(rows),
      damping(rows), smoothness(rows);
  for (py::ssize_t i = 0; i < rows; ++i) {
    const FitIteration& row = report.history[static_cast<std::size_t>(i)];
    iteration.mutable_at(i) = row.iteration;
    objective.mutable_at(i) = row.objective;
    rms.mutable_at(i) = row.rmsDistance;
    max.mutable_at(i) = row.maxDistance;
    step.mutable_at(i) = row.stepLength;
    move.mutable_at(i) = row.targetMove;
    scale.mutable_at(i) = row.stepScale;
    damping.mutable_at(i) = row.damping;
    smoothness.mutable_at(i) = row.smoothness;
  }
  py::dict history;
  history["iteration"] = iteration;
  history["objective"] = objective;
  history["rms_distance"] = rms;
  history["max_distance"] = max;
  history["step_length"] = step;
  history["target_move"] = move;
  history["step_scale"] = scale;
  history["damping"] = damping;
  history["smoothness"] = smoothness;
  return history;
}

// The fit target of a Python object, as loadFitTarget() makes it of a file's content.
FitTarget fitTargetOf(const py::handle& target, FitSpline spline, double offset) {
  FitTargetOptions options;
  options.spline = spline;
  options.offset = offset;
  if (py::isinstance<Field>(target)) {
    return fitTargetFromField(target.cast<const Field&>().field, "the field", options);
  }
  if (py::isinstance<LevelSet>(target) || py::isinstance<TriangleMesh>(target)) {
    throw InputError("fit to d2vdb.Field(target): the fitters query a target's approximant field");
  }
  LoadedInput input = inputOf(target, "the target");
  return fitTargetFromInput(std::move(input), options);
}

FitResult fitCurveFrom(const py::object& target, const py::object& initial, int controlPoints,
                       int degree, bool closed, double offset, int sensors,
                       bool footpointCorrection, int threads, const py::object& progress,
                       const py::kwargs& options) {
  const FitKeywords keywords = keywordsFrom(options);
  if (!std::isfinite(offset)) throw InputError("offset must be finite");
  const FitTarget fitTarget = fitTargetOf(target, FitSpline::Curve, offset);
  const BSplineCurve start = py::isinstance<BSplineCurve>(initial)
                                 ? initial.cast<BSplineCurve>()
                                 : initialCurveForTarget(fitTarget, initial.cast<std::string>(),
                                                         degree, controlPoints, closed, offset);
  CurveFitOptions fit;
  keywords.applyTo(fit);
  fit.sensorsPerSpan = sensors;
  fit.footpointCorrection = footpointCorrection;
  CurveFitResult result =
      runLong<CurveFitResult>(progress, threads, [&](const ProgressCallback& report) {
        CurveFitOptions withProgress = fit;
        withProgress.progress = report;
        if (fitTarget.kind == InputKind::PointSet) {
          return fitCurveToPoints(start, fitTarget.points, withProgress);
        }
        return fitCurve(start, fitTarget.fitTarget(), withProgress);
      });
  return {py::cast(std::move(result.curve)), fitStatusName(result.status), result.reason,
          historyArrays(result)};
}

FitResult fitSurfaceFrom(const py::object& target, const py::object& initial,
                         const std::pair<int, int>& controlPoints,
                         const std::pair<int, int>& degree, bool closedU, bool closedV, bool ruled,
                         double offset, int sensors, bool reparametrize, int threads,
                         const py::object& progress, const py::kwargs& options) {
  const FitKeywords keywords = keywordsFrom(options);
  if (!std::isfinite(offset)) throw InputError("offset must be finite");
  const FitTarget fitTarget = fitTargetOf(target, FitSpline::Surface, offset);
  const BSplineSurface start = [&] {
    if (py::isinstance<BSplineSurface>(initial)) return initial.cast<BSplineSurface>();
    SurfaceLayout layout;
    layout.degreeU = ruled ? 1 : degree.first;
    layout.degreeV = degree.second;
    layout.countU = controlPoints.first;
    layout.countV = controlPoints.second;
    layout.closedU = closedU;
    layout.closedV = closedV;
    return initialSurfaceForTarget(fitTarget, initial.cast<std::string>(), layout, offset);
  }();
  SurfaceFitOptions fit;
  keywords.applyTo(fit);
  fit.sensorsPerSpan = sensors;
  fit.reparametrize = reparametrize;
  SurfaceFitResult result =
      runLong<SurfaceFitResult>(progress, threads, [&](const ProgressCallback& report) {
        SurfaceFitOptions withProgress = fit;
        withProgress.progress = report;
        if (fitTarget.kind == InputKind::PointSet) {
          return fitSurfaceToPoints(start, fitTarget.points, withProgress);
        }
        return fitSurface(start, fitTarget.fitTarget(), withProgress);
      });
  return {py::cast(std::move(result.surface)), fitStatusName(result.status), result.reason,
          historyArrays(result)};
}

constexpr const char* kFitOptionsDoc =
    " Further keywords, as the command's options: method ('pdm', 'tdm', 'sdm', 'tdm+pdm'), "
    "iterations (cap), smoothness (None: automatic), smoothing_bias, step_smoothness, stretch, "
    "pdm_weight, tolerance (stop at this RMS distance, world units), step_tolerance, "
    "move_tolerance, exact_second_order. threads: TBB threads (0: all cores; results do not "
    "depend on it); progress: None or callable(stage, fraction). Returns a FitResult: the "
    "spline, status ('converged', 'stalled', 'iteration cap'), reason and history (dict of "
    "arrays, row 0 the initial spline). Raises InputError as the command does.";

}  // namespace

void bindFit(py::module_& module) {
  py::class_<FitResult>(module, "FitResult", "The outcome of fit_curve() or fit_surface().")
      .def_readonly("spline", &FitResult::spline, "The fitted Curve or Surface (same knots).")
      .def_readonly("status", &FitResult::status)
      .def_readonly("reason", &FitResult::reason, "One line saying why the fit stopped.")
      .def_readonly("history", &FitResult::history,
                    "Arrays per iteration (row 0: the initial spline): iteration, objective, "
                    "rms_distance, max_distance (world units), step_length, target_move, "
                    "step_scale, damping, smoothness.")
      .def("__repr__", [](const FitResult& result) {
        return "<d2vdb.FitResult " + result.status + ": " + result.reason + ">";
      });

  module.def("fit_curve", &fitCurveFrom, py::arg("target"), py::arg("initial") = "ellipse",
             py::kw_only(), py::arg("control_points") = 12, py::arg("degree") = 3,
             py::arg("closed") = false, py::arg("offset") = 0.0, py::arg("sensors") = 8,
             py::arg("footpoint_correction") = true, py::arg("threads") = 0,
             py::arg("progress") = py::none(),
             (std::string("Fits a B-spline curve to a target as `d2vdb fit-curve` does: a Field "
                          "(of a curve, points or a surface), a Curve, or a PointSet / (N, 3) "
                          "points (SDM II). initial: a Curve, or 'circle', 'ellipse' or "
                          "'polyline' generated around the target with control_points and "
                          "degree (closed: a closed polyline fit). offset: fit the offset of a "
                          "curve target at this distance.") +
              kFitOptionsDoc)
                 .c_str());
  module.def("fit_surface", &fitSurfaceFrom, py::arg("target"), py::arg("initial") = "plane",
             py::kw_only(), py::arg("control_points") = std::pair<int, int>{8, 8},
             py::arg("degree") = std::pair<int, int>{3, 3}, py::arg("closed_u") = false,
             py::arg("closed_v") = false, py::arg("ruled") = false, py::arg("offset") = 0.0,
             py::arg("sensors") = 6, py::arg("reparametrize") = true, py::arg("threads") = 0,
             py::arg("progress") = py::none(),
             (std::string("Fits a tensor-product B-spline surface to a target as `d2vdb "
                          "fit-surface` does: the Field of a surface (SDM I), a Surface, or a "
                          "PointSet / (N, 3) points (SDM II). initial: a Surface, or 'plane', "
                          "'cylinder' or 'torus' placed around the target with control_points "
                          "(m, n), degree (p, q), closed_u/closed_v and ruled (degree 1 in u). "
                          "offset: fit the offset at this distance (not point clouds); "
                          "reparametrize=False is the command's --no-restart.") +
              kFitOptionsDoc)
                 .c_str());
}

}  // namespace d2vdb::python
