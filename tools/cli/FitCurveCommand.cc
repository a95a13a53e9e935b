// d2vdb fit-curve: fits a B-spline curve to a curve, an offset of a curve, a point cloud or a
// distance field by squared distance minimisation (PDM, TDM, SDM, TDM+PDM), printing
// the iteration history and optionally drawing the iterates and the convergence as SVG.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "CertifiedFitError.h"
#include "Command.h"
#include "ConvergencePlot.h"
#include "FitReports.h"
#include "d2vdb/core/AtomicFileSet.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/fit/CurveFitter.h"
#include "d2vdb/fit/InitialCurve.h"
#include "d2vdb/fit/PointCloudFitter.h"
#include "d2vdb/io/FitTarget.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/plot/SvgCanvas.h"

namespace d2vdb::cli {
namespace {

struct FitCurveArguments {
  std::string target, init = "ellipse", method = "sdm", out, svg, plot;
  int degree = 3;
  int controlPoints = 12;
  bool closed = false;
  double offset = 0.0;
  double certify = 0.0;  ///< --certify: relative bracket width, 0 for none
  int every = 1;
  bool compare = false;
  bool plainSdm = false;
  bool noFootpointCorrection = false;
  CurveFitOptions fit;
};

void declareFitCurveOutputs(CLI::App& command, FitCurveArguments& args) {
  command.add_flag("--no-footpoint-correction", args.noFootpointCorrection,
                   "SDM on point clouds without correcting each step by the least-squares fit "
                   "for the footpoint parameters it reached (for comparison)");
  command.add_option("--svg", args.svg, "Draw target, initial, iterates and final curve (SVG)");
  command.add_option("--every", args.every, "With --svg: draw every k-th iterate")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  command.add_option("--plot", args.plot, "Plot the RMS distance per iteration (SVG, log scale)");
  command.add_flag("--compare", args.compare,
                   "Also run PDM and SDM from the same initial curve; report and plot them");
  declareCertifyOption(command, args.certify);
}

void declareFitCurve(CLI::App& command, FitCurveArguments& args) {
  command.add_option("--target", args.target, "Target: curve/polyline .json, .xyz/.ply, .vdb")
      ->required();
  command
      .add_option("--init", args.init,
                  "Initial curve: 'circle' or 'ellipse' around the target (closed), 'polyline' "
                  "(least-squares fit to the target's points in order), or a curve .json")
      ->capture_default_str();
  command.add_option("--method", args.method, "pdm, tdm, sdm or tdm+pdm")->capture_default_str();
  command.add_option("--degree", args.degree, "Degree of a generated initial curve")
      ->capture_default_str()
      ->check(CLI::Range(1, 15));
  command.add_option("--ctrl", args.controlPoints, "Control points of a generated initial curve")
      ->capture_default_str()
      ->check(CLI::Range(2, 1000000));
  command.add_flag("--closed", args.closed, "With --init polyline: fit a closed curve");
  command.add_option("--offset", args.offset, "Fit the offset at this distance (curve targets)")
      ->check(positiveNumber());
  command.add_option("--out", args.out, "Write the fitted curve (.json)")->required();
  command.add_option("--sensors", args.fit.sensorsPerSpan, "Sensors per knot span (SDM I)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  declareFitOptions(command, args.fit, args.plainSdm,
                    {"curve",
                     "Weight of int |x''|^2 (dimensionless; default: automatic, its bias held at "
                     "--smoothing-bias x the fit's precision; none for open curves on a curve or "
                     "field target)",
                     "Weight of int |x'|^2 (dimensionless)",
                     "SDM on point clouds without the exact second-order terms (Wang, Pottmann and "
                     "Liu 2006 as published; for comparison)"});
  declareFitCurveOutputs(command, args);
}

bool isCurve(InputKind kind) {
  return kind == InputKind::Curve || kind == InputKind::Polylines;
}

// Refuses more control points than the target can determine, before any work: a point cloud's
// points each give one equation; a curve target is resolved once the fitted curve has 100 spans
// per vertex or control point of it (at least 1000 control points); a field, 100000.
void checkControlPointCount(int controlPoints, const FitTarget& target) {
  std::size_t limit = 100000;
  std::string why = "a field target";
  if (target.kind == InputKind::PointSet) {
    limit = target.points.size();
    why = "the " + std::to_string(limit) + " points of the target, which cannot determine more";
  } else if (isCurve(target.kind)) {
    limit = std::max<std::size_t>(1000, 100 * target.pieces);
    why = "100 per " + std::string(target.kind == InputKind::Curve ? "control point" : "vertex") +
          " of the target (" + std::to_string(target.pieces) +
          "), beyond which spans are finer than anything it describes";
  }
  if (static_cast<std::size_t>(controlPoints) > limit) {
    throw InputError("--ctrl " + std::to_string(controlPoints) +
                     " asks for more control points "
                     "than " +
                     why + "; use --ctrl " + std::to_string(limit) + " or fewer");
  }
}

BSplineCurve initialCurve(const FitCurveArguments& args, const FitTarget& target) {
  const std::string& init = args.init;
  if (init == "circle" || init == "ellipse" || init == "polyline") {
    return initialCurveForTarget(target, init, args.degree, args.controlPoints, args.closed,
                                 args.offset);
  }
  LoadOptions load;
  load.purpose = "the initial curve (--init)";
  return loadInputAs<BSplineCurve>(init, load);
}

CurveFitResult runFit(const BSplineCurve& initial, const FitTarget& target,
                      const CurveFitOptions& options) {
  if (target.kind == InputKind::PointSet) return fitCurveToPoints(initial, target.points, options);
  return fitCurve(initial, target.fitTarget(), options);
}

// Target (grey), initial curve (dashed blue), every k-th iterate (light), final curve (red),
// projected onto the xy plane, y up.
void writeIterationSvg(const std::string& file, const FitTarget& target,
                       const CurveFitResult& result, int every) {
  std::vector<std::vector<Eigen::Vector3d>> iterates;
  for (const BSplineCurve& curve : result.iterates) iterates.push_back(curve.sample(600));
  std::vector<Eigen::Vector3d> everything = target.points;
  for (const auto& samples : iterates)
    everything.insert(everything.end(), samples.begin(), samples.end());
  SvgCanvas canvas = SvgCanvas::forPoints(everything);
  const double stroke = 0.0027 * canvas.extent();  // 0.3% of the drawing's extent
  canvas.comment("d2vdb fit-curve: target (grey), initial curve (dashed blue), every " +
                 std::to_string(every) +
                 "-th iterate (light blue), final curve (red); xy projection");
  if (target.kind == InputKind::PointSet) {
    const SvgStyle dot = SvgStyle::filled("#808080");
    const std::size_t stride = std::max<std::size_t>(1, target.points.size() / 5000);
    for (std::size_t i = 0; i < target.points.size(); i += stride) {
      canvas.circle(target.points[i], stroke, dot);
    }
  } else {
    canvas.polyline(target.points, SvgStyle::stroked("#808080", 2.0 * stroke), target.closed);
  }
  for (std::size_t k = 1; k + 1 < iterates.size(); ++k) {
    if (static_cast<int>(k) % every == 0) {
      canvas.polyline(iterates[k], SvgStyle::stroked("#9db4d8", 0.6 * stroke));
    }
  }
  if (!iterates.empty()) {
    canvas.polyline(iterates.front(), SvgStyle::stroked("#1f4e9c", stroke, "6 4"));
    canvas.polyline(iterates.back(), SvgStyle::stroked("#b3261e", stroke));
  }
  canvas.write(file);
}

using ComparedFits = std::vector<std::pair<FitMethod, CurveFitResult>>;

// --compare: PDM and SDM (whichever was not the method) from the same initial curve.
ComparedFits compareFits(const BSplineCurve& initial, const FitTarget& target,
                         const CurveFitOptions& fit) {
  ComparedFits extra;
  for (const FitMethod other : {FitMethod::PDM, FitMethod::SDM}) {
    if (other == fit.method) continue;
    CurveFitOptions otherFit = fit;
    otherFit.method = other;
    otherFit.keepIterates = false;
    extra.emplace_back(other, runFit(initial, target, otherFit));
  }
  return extra;
}

void writePlot(const std::string& file, FitMethod method, const CurveFitResult& result,
               const ComparedFits& extra) {
  std::vector<ConvergenceSeries> runs = {
      {method, &result.history, result.iterations(), result.status}};
  for (const auto& [other, otherResult] : extra) {
    runs.push_back({other, &otherResult.history, otherResult.iterations(), otherResult.status});
  }
  writeConvergencePlot(file, runs, "fit-curve");
}

nlohmann::json fitCurveJson(const FitCurveArguments& args, const FitTarget& target,
                            const BSplineCurve& initial, FitMethod method,
                            const CurveFitResult& result, const ComparedFits& extra) {
  nlohmann::json json = fitReportJson(result, method);
  json["target"] = args.target;
  json["target_kind"] = inputKindName(target.kind);
  json["offset"] = args.offset;
  json["dimension"] = initial.dimension();
  json["degree"] = initial.degree();
  json["control_points"] = initial.controlPointCount();
  json["closed"] = initial.isClosed();
  json["output"] = args.out;
  if (!args.svg.empty()) json["svg"] = args.svg;
  if (!args.plot.empty()) json["plot"] = args.plot;
  if (args.compare) {
    nlohmann::json compare = {{fitMethodName(method), fitReportJson(result, method)}};
    for (const auto& [other, otherResult] : extra) {
      compare[fitMethodName(other)] = fitReportJson(otherResult, other);
    }
    json["compare"] = compare;
  }
  return json;
}

Report runFitCurve(const FitCurveArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  const FitMethod method = parseFitMethod(args.method);
  checkInitOption(args.init, {"circle", "ellipse", "polyline"}, "a B-spline curve .json");
  FitTargetOptions load;
  load.spline = FitSpline::Curve;
  load.offset = args.offset;
  load.purpose = "the target of 'd2vdb fit-curve'";
  load.progress = context.progress();
  const FitTarget target = loadFitTarget(args.target, load);
  const std::optional<HausdorffInput> certifyAgainst =
      certifyTarget(args.target, args.certify, args.offset, context);
  checkControlPointCount(args.controlPoints, target);
  const BSplineCurve initial = initialCurve(args, target);
  CurveFitOptions fit = args.fit;
  fit.method = method;
  fit.exactSecondOrder = !args.plainSdm;
  fit.footpointCorrection = !args.noFootpointCorrection;
  fit.keepIterates = !args.svg.empty();
  fit.progress = context.progress();
  const CurveFitResult result = runFit(initial, target, fit);
  const ComparedFits extra = args.compare ? compareFits(initial, target, fit) : ComparedFits{};

  // All outputs to temporary names; none replaces its target unless all were written.
  AtomicFileSet files;
  files.stage(args.out, [&](const std::filesystem::path& temporary) {
    writeCurveJson(temporary, result.curve);
  });
  if (!args.svg.empty()) {
    files.stage(args.svg, [&](const std::filesystem::path& temporary) {
      writeIterationSvg(temporary.string(), target, result, args.every);
    });
  }
  if (!args.plot.empty()) {
    files.stage(args.plot, [&](const std::filesystem::path& temporary) {
      writePlot(temporary.string(), method, result, extra);
    });
  }
  files.commit();

  std::string text = fitReportText(result, method);
  for (const auto& [other, otherResult] : extra) text += fitReportText(otherResult, other);
  nlohmann::json json = fitCurveJson(args, target, initial, method, result, extra);
  if (certifyAgainst) {
    std::string line;
    json["certified"] = certifiedFitError(hausdorffInputOfCurve(result.curve), *certifyAgainst,
                                          args.certify, context, line);
    text += line;
  }
  return fitAnswer(std::move(json), std::move(text), clock.seconds(), args.out, context);
}

std::vector<OutputFile> outputsOfFitCurve(const FitCurveArguments& args) {
  return {{"--out", args.out, OutputFormat::Json},
          {"--svg", args.svg, OutputFormat::Svg},
          {"--plot", args.plot, OutputFormat::Svg}};
}

}  // namespace

void addFitCurveCommand(CommandRegistry& registry) {
  registry.add<FitCurveArguments>(
      {"fit-curve",
       "Fit a B-spline curve (knots fixed) to a target by squared distance minimisation: a curve "
       "or polyline .json (SDM I; --offset R fits the offset at distance R), a point cloud "
       ".xyz/.ply (SDM II: errors orthogonal to the active curve) or a distance field .vdb. "
       "Prints the iteration history (objective, RMS and max distance, step) and why it "
       "stopped.\n"
       "Example: d2vdb fit-curve --target volumes/ellipse.json --init circle --method sdm --ctrl "
       "12 "
       "--out fitted.json --svg fit.svg --plot conv.svg --compare",
       "use fewer control points (--ctrl) or sensors (--sensors), or a smaller target",
       declareFitCurve, runFitCurve, outputsOfFitCurve});
}

}  // namespace d2vdb::cli
