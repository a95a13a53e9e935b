// d2vdb hausdorff: the Hausdorff distance between two shapes as a certified bracket. Two B-spline
// curves get the exact method of Chen et al. (2010), optionally drawn as SVG; meshes, point sets,
// level sets, curves and surfaces in any other pairing get the branch and bound of
// measure/MeshHausdorff.h, optionally with a heat map and a histogram of A's distances.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "Command.h"
#include "JsonReports.h"
#include "ReportText.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/io/HausdorffInput.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/measure/CurveHausdorff.h"
#include "d2vdb/measure/MeshHausdorff.h"
#include "d2vdb/mesh/DistanceColors.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/SurfaceTessellation.h"
#include "d2vdb/plot/Histogram.h"
#include "d2vdb/plot/SvgCanvas.h"
#include "d2vdb/spline/CurvePolyline.h"

namespace d2vdb::cli {
namespace {

struct HausdorffArguments {
  std::string a, b, svg, heatmap, histogram;
  bool oneSided = false;
  bool relative = false;
  double tolerance = 0.0;  ///< 0: not given (the kind of pair chooses the default)
  int maxDepth = 0;        ///< 0: not given
};

/// Significant digits of the text report.
constexpr int kDistanceDigits = 15;
/// Default of --tolerance for two curves, relative to their size (other shapes: HausdorffRequest).
constexpr double kDefaultCurveTolerance = 1e-10;
/// Bins of the --histogram chart.
constexpr int kHistogramBins = 40;

void declareHausdorff(CLI::App& command, HausdorffArguments& args) {
  command
      .add_option("a", args.a,
                  "Shape A: mesh (.obj .ply .stl), points (.xyz .ply), level "
                  "set (.vdb), B-spline curve or surface (.json)")
      ->required();
  command.add_option("b", args.b, "Shape B, of the same kinds")->required();
  command.add_flag("--one-sided", args.oneSided, "Only h(A -> B)");
  command.add_option("--svg", args.svg,
                     "Two curves: draw both and the Hausdorff pair into this SVG file (xy plane)");
  command.add_option("--heatmap", args.heatmap,
                     "Write A's vertices with their distance to B into this PLY (a 'distance' "
                     "property and colours, as MeshLab, Blender and Houdini read them)");
  command.add_option("--histogram", args.histogram,
                     "Draw the distribution of A's vertex distances to B into this SVG file");
  command
      .add_option("--tolerance", args.tolerance,
                  "Width of the certified bracket, in world units (with --relative: of the "
                  "diagonal of both shapes' bounding box). Default: relative 1e-6, or 1e-10 for "
                  "two curves")
      ->check(CLI::PositiveNumber);
  command.add_flag("--relative", args.relative,
                   "Take --tolerance relative to the diagonal of both shapes' bounding box");
  command
      .add_option("--max-depth", args.maxDepth,
                  "Bound on the halvings of one primitive (curves: of a knot span, 1-200, "
                  "default 64; other shapes: of a triangle's edges, 1-40, default 28)")
      ->check(CLI::Range(1, 200));
}

// The curve method's options: --tolerance made relative to the curves' size (the diagonal of
// their control points' box, as HausdorffOptions::relativeTolerance takes it).
HausdorffOptions curveOptions(const HausdorffArguments& args, const BSplineCurve& a,
                              const BSplineCurve& b) {
  HausdorffOptions options;
  if (args.maxDepth > 0) options.maxDepth = args.maxDepth;
  if (args.tolerance <= 0.0) {
    options.relativeTolerance = kDefaultCurveTolerance;
  } else if (args.relative) {
    options.relativeTolerance = args.tolerance;
  } else {
    Eigen::AlignedBox3d box;
    for (const auto* curve : {&a, &b}) {
      for (const Eigen::Vector3d& point : curve->controlPoints()) box.extend(point);
    }
    const double size = box.diagonal().norm();
    options.relativeTolerance = size > 0.0 ? args.tolerance / size : args.tolerance;
  }
  if (!(options.relativeTolerance <= 0.1)) {
    throw InputError("--tolerance " + formatNumber(args.tolerance) +
                     " is more than a tenth of the curves' size: nothing would be certified");
  }
  options.relativeTolerance = std::max(options.relativeTolerance, 1e-15);
  return options;
}

// H(a, b), or with --one-sided h(a -> b) alone as the larger direction (bToA stays empty).
HausdorffDistance computeDistance(const HausdorffArguments& args, const HausdorffOptions& options,
                                  const BSplineCurve& a, const BSplineCurve& b) {
  if (!args.oneSided) return hausdorffDistance(a, b, options);
  HausdorffDistance result;
  result.aToB = oneSidedHausdorff(a, b, options);
  result.distance = result.aToB.distance;
  result.lowerBound = result.aToB.lowerBound;
  result.upperBound = result.aToB.upperBound;
  result.aToBIsLarger = true;
  return result;
}

nlohmann::json oneSidedJson(const OneSidedHausdorff& result, int fromDimension, int toDimension) {
  return {{"distance", result.distance},
          {"lower_bound", result.lowerBound},
          {"upper_bound", result.upperBound},
          {"from_parameter", result.fromParameter},
          {"to_parameter", result.toParameter},
          {"from_point", pointJson(result.fromPoint, fromDimension)},
          {"to_point", pointJson(result.toPoint, toDimension)},
          {"case", static_cast<int>(result.pairCase)},
          {"case_name", hausdorffCaseName(result.pairCase)},
          {"converged", result.converged},
          {"intervals", result.intervalsExamined},
          {"depth", result.deepestLevel}};
}

nlohmann::json hausdorffJson(const HausdorffArguments& args, const HausdorffOptions& options,
                             const BSplineCurve& a, const BSplineCurve& b,
                             const HausdorffDistance& result,
                             const std::vector<std::string>& warnings, double seconds) {
  nlohmann::json report = {
      {"a", args.a},
      {"b", args.b},
      {"one_sided", args.oneSided},
      {"distance", result.distance},
      {"lower_bound", result.lowerBound},
      {"upper_bound", result.upperBound},
      {"larger_direction", result.aToBIsLarger ? "a_to_b" : "b_to_a"},
      {"method", "curves"},
      {"relative_tolerance", options.relativeTolerance},
      {"converged", result.aToB.converged && (args.oneSided || result.bToA.converged)},
      {"a_to_b", oneSidedJson(result.aToB, a.dimension(), b.dimension())},
      {"seconds", seconds},
      {"warnings", warnings},
  };
  if (!args.oneSided) report["b_to_a"] = oneSidedJson(result.bToA, b.dimension(), a.dimension());
  if (!args.svg.empty()) report["svg"] = args.svg;
  return report;
}

std::string oneSidedText(const std::string& name, const OneSidedHausdorff& result) {
  std::ostringstream text;
  text.precision(kDistanceDigits);
  text << "  " << name << " = " << result.distance << "  bracket [" << result.lowerBound << ", "
       << result.upperBound << "]\n"
       << "    pair u = " << result.fromParameter << " "
       << formatPoint(result.fromPoint, kDistanceDigits) << ", v = " << result.toParameter << " "
       << formatPoint(result.toPoint, kDistanceDigits) << ", case "
       << static_cast<int>(result.pairCase) << ": " << hausdorffCaseName(result.pairCase) << '\n';
  return text.str();
}

std::string hausdorffText(const HausdorffArguments& args, const HausdorffDistance& result) {
  std::ostringstream text;
  text.precision(kDistanceDigits);
  text << (args.oneSided ? "one-sided Hausdorff distance h(A -> B) = "
                         : "Hausdorff distance H(A, B) = ")
       << result.distance << "  bracket [" << result.lowerBound << ", " << result.upperBound
       << "]\n"
       << oneSidedText("h(A -> B)", result.aToB);
  if (!args.oneSided) text << oneSidedText("h(B -> A)", result.bToA);
  return text.str();
}

// Both curves as polylines, their control polygons, and the Hausdorff pair as a segment with its
// two points, projected onto the xy plane (y up).
void writeSvg(const std::string& file, const BSplineCurve& a, const BSplineCurve& b,
              const OneSidedHausdorff& pair) {
  const std::vector<std::vector<Eigen::Vector3d>> polylines = drawingPolylines({a, b});
  const std::vector<Eigen::Vector3d>& pointsA = polylines[0];
  const std::vector<Eigen::Vector3d>& pointsB = polylines[1];
  std::vector<Eigen::Vector3d> everything = pointsA;
  for (const auto* points : {&pointsB, &a.controlPoints(), &b.controlPoints()}) {
    everything.insert(everything.end(), points->begin(), points->end());
  }
  SvgCanvas canvas = SvgCanvas::forPoints(everything);
  const double stroke = 0.0036 * canvas.extent();  // 0.4% of the curves' extent
  canvas.comment(
      "d2vdb hausdorff: curve A (blue), curve B (red), control polygons (thin), Hausdorff pair "
      "(black); 3D curves are drawn projected onto the xy plane");
  canvas.polyline(a.controlPoints(), SvgStyle::stroked("#9db4d8", 0.5 * stroke, "4 3"));
  canvas.polyline(b.controlPoints(), SvgStyle::stroked("#e0a8a8", 0.5 * stroke, "4 3"));
  canvas.polyline(pointsA, SvgStyle::stroked("#1f4e9c", stroke));
  canvas.polyline(pointsB, SvgStyle::stroked("#b3261e", stroke));
  canvas.line(pair.fromPoint, pair.toPoint, SvgStyle::stroked("black", stroke));
  const SvgStyle dot = SvgStyle::filled("black");
  for (const Eigen::Vector3d& point : {pair.fromPoint, pair.toPoint}) {
    canvas.circle(point, 2.5 * stroke, dot);
  }
  canvas.write(file);
}

Report runCurveHausdorff(const HausdorffArguments& args, const BSplineCurve& a,
                         const BSplineCurve& b, const Stopwatch& clock,
                         const CommandContext& context) {
  const HausdorffOptions options = curveOptions(args, a, b);
  const HausdorffDistance result = computeDistance(args, options, a, b);
  std::vector<std::string> warnings = result.aToB.warnings;
  if (!args.oneSided) {
    warnings.insert(warnings.end(), result.bToA.warnings.begin(), result.bToA.warnings.end());
  }
  for (const std::string& message : warnings) warning(message);
  if (!args.svg.empty()) {
    writeSvg(args.svg, a, b, result.aToBIsLarger ? result.aToB : result.bToA);
    printSummaryLineNow(context, "wrote " + args.svg);
  }
  return {hausdorffJson(args, options, a, b, result, warnings, clock.seconds()),
          hausdorffText(args, result), Report::Text::Answer};
}

// ---- Meshes, points, level sets and splines in any other pairing ----

nlohmann::json bracketJson(const DirectedHausdorffBracket& bracket) {
  nlohmann::json json = {{"distance", bracket.lower},
                         {"lower_bound", bracket.lower},
                         {"upper_bound", bracket.upper},
                         {"from_point", pointJson(bracket.witness)},
                         {"to_point", pointJson(bracket.witnessClosest)},
                         {"primitives_refined", bracket.primitivesRefined},
                         {"depth", bracket.deepestLevel},
                         {"converged", bracket.converged}};
  if (!bracket.warning.empty()) json["warning"] = bracket.warning;
  return json;
}

nlohmann::json shapeJson(const std::string& file, const HausdorffInput& input,
                         const HausdorffShape& shape) {
  return {{"file", file},
          {"kind", inputKindName(input.kind)},
          {"primitives", shape.triangles.size()},
          {"as", shape.description},
          {"approximation_error", shape.approximationError}};
}

std::string bracketText(const std::string& name, const DirectedHausdorffBracket& bracket) {
  std::ostringstream text;
  text.precision(kDistanceDigits);
  text << "  " << name << " bracket [" << bracket.lower << ", " << bracket.upper << "]\n"
       << "    at " << formatPoint(bracket.witness, kDistanceDigits) << ", nearest "
       << formatPoint(bracket.witnessClosest, kDistanceDigits) << "; " << bracket.primitivesRefined
       << " primitives refined, depth " << bracket.deepestLevel << '\n';
  return text.str();
}

TriangleMesh curveSamples(const BSplineCurve& curve) {
  TriangleMesh samples;
  for (const Eigen::Vector3d& point : curve.sample(1001))
    samples.positions.push_back(point.cast<float>());
  return samples;
}

std::vector<Eigen::Vector3d> positionsOf(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> positions;
  positions.reserve(mesh.positions.size());
  for (const Eigen::Vector3f& position : mesh.positions)
    positions.push_back(position.cast<double>());
  return positions;
}

/// A's distances to B at its points (a spline's at a display tessellation: 101 x 101 samples of a
/// surface, 1001 of a curve): the heat map's vertices and the histogram's values.
void writeDistanceOutputs(const HausdorffArguments& args, const HausdorffInput& input,
                          const HausdorffShape& shape, const HausdorffShape& target,
                          const DirectedHausdorffBracket& aToB, const CommandContext& context) {
  if (args.heatmap.empty() && args.histogram.empty()) return;
  // A's own vertices, or for a spline a display tessellation of it.
  const TriangleMesh mesh = input.surface ? tessellate(*input.surface, 101, 101)
                            : input.curve ? curveSamples(*input.curve)
                                          : meshOfShape(shape);
  const std::vector<double> distances =
      shape.nets.empty() ? aToB.pointDistances : pointDistancesTo(target, positionsOf(mesh));
  if (!args.heatmap.empty()) {
    const double largest = *std::max_element(distances.begin(), distances.end());
    VertexAttributes attributes;
    attributes.scalarName = "distance";
    for (const double distance : distances) {
      attributes.scalars.push_back(static_cast<float>(distance));
      attributes.colors.push_back(distanceColor(distance, largest));
    }
    writeMesh(args.heatmap, mesh, attributes);
    printSummaryLineNow(context, "wrote " + args.heatmap);
  }
  if (!args.histogram.empty()) {
    HistogramLabels labels;
    labels.title = "Distances from the vertices of A to B";
    labels.xAxis = "distance (world units)";
    labels.yAxis = "vertices";
    labels.description = "d2vdb hausdorff " + args.a + " " + args.b;
    histogramPlot(distances, kHistogramBins, labels).write(args.histogram);
    printSummaryLineNow(context, "wrote " + args.histogram);
  }
}

Report runShapeHausdorff(const HausdorffArguments& args, const HausdorffInput& inputA,
                         const HausdorffInput& inputB, const Stopwatch& clock,
                         const CommandContext& context) {
  HausdorffRequest request;
  request.tolerance = args.tolerance;
  request.relative = args.relative;
  request.oneSided = args.oneSided;
  if (args.maxDepth > 40) throw InputError("--max-depth must be at most 40 for these shapes");
  request.maxDepth = args.maxDepth;
  request.progress = context.progress();
  const HausdorffComparison pair = compareHausdorff(inputA, inputB, request);
  const CertifiedHausdorff& result = pair.result;
  std::vector<std::string> warnings;
  for (const DirectedHausdorffBracket* bracket : {&result.aToB, &result.bToA}) {
    if (!bracket->warning.empty()) warnings.push_back(bracket->warning);
  }
  for (const std::string& message : warnings) warning(message);
  writeDistanceOutputs(args, inputA, pair.a, pair.b, result.aToB, context);

  nlohmann::json json = {
      {"a", args.a},
      {"b", args.b},
      {"method", "branch and bound"},
      {"one_sided", args.oneSided},
      {"distance", result.lower},
      {"lower_bound", result.lower},
      {"upper_bound", result.upper},
      {"tolerance", pair.tolerance},
      {"diagonal", pair.diagonal},
      {"larger_direction", result.aToBIsLarger ? "a_to_b" : "b_to_a"},
      {"converged", result.aToB.converged && (args.oneSided || result.bToA.converged)},
      {"shape_a", shapeJson(args.a, inputA, pair.a)},
      {"shape_b", shapeJson(args.b, inputB, pair.b)},
      {"a_to_b", bracketJson(result.aToB)},
      {"seconds", clock.seconds()},
      {"warnings", warnings}};
  if (!args.oneSided) json["b_to_a"] = bracketJson(result.bToA);
  if (!args.heatmap.empty()) json["heatmap"] = args.heatmap;
  if (!args.histogram.empty()) json["histogram"] = args.histogram;

  std::ostringstream text;
  text.precision(kDistanceDigits);
  text << (args.oneSided ? "one-sided Hausdorff distance h(A -> B) in ["
                         : "Hausdorff distance H(A, B) in [")
       << result.lower << ", " << result.upper << "] (tolerance " << pair.tolerance << ")\n"
       << bracketText("h(A -> B)", result.aToB);
  if (!args.oneSided) text << bracketText("h(B -> A)", result.bToA);
  text << "  A: " << pair.a.description << ", " << pair.a.triangles.size()
       << " primitives; B: " << pair.b.description << ", " << pair.b.triangles.size()
       << " primitives\n";
  return {json, text.str(), Report::Text::Answer};
}

Report runHausdorff(const HausdorffArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  LoadOptions load;
  load.purpose = "each shape given to 'd2vdb hausdorff'";
  HausdorffInput a = loadHausdorffInput(args.a, load, context.progress());
  HausdorffInput b = loadHausdorffInput(args.b, load, context.progress());
  const bool curves = a.kind == InputKind::Curve && b.kind == InputKind::Curve;
  if (curves && (!args.heatmap.empty() || !args.histogram.empty())) {
    throw InputError(
        "--heatmap and --histogram are for meshes, points, level sets and surfaces; "
        "two curves get the exact curve method (draw it with --svg)");
  }
  if (!curves && !args.svg.empty()) {
    throw InputError("--svg draws two curves; for other shapes use --heatmap or --histogram");
  }
  if (curves) return runCurveHausdorff(args, *a.curve, *b.curve, clock, context);
  return runShapeHausdorff(args, a, b, clock, context);
}

std::vector<OutputFile> outputsOfHausdorff(const HausdorffArguments& args) {
  return {{"--svg", args.svg, OutputFormat::Svg},
          {"--heatmap", args.heatmap, OutputFormat::Ply},
          {"--histogram", args.histogram, OutputFormat::Svg}};
}

}  // namespace

void addHausdorffCommand(CommandRegistry& registry) {
  registry.add<HausdorffArguments>(
      {"hausdorff",
       "Hausdorff distance H(A, B) = max(h(A -> B), h(B -> A)), h(A -> B) = max over A of the "
       "distance to B, as a certified bracket [lower, upper] no wider than --tolerance, with both "
       "one-sided brackets and the points that attain them. Two B-spline curves (.json) get the "
       "exact method of Chen et al. (2010), with the case of each pair. Meshes, point sets, level "
       "sets (the marching-cubes mesh of their zero set at the grid's resolution) and B-spline "
       "curves and surfaces (tessellated with a certified error) in any pairing get a branch and "
       "bound over A's triangles whose bracket also holds in exact arithmetic.\n"
       "Example: d2vdb hausdorff fitted.json volumes/helix.json --svg pair.svg --json\n"
       "         d2vdb hausdorff volumes/bunny.obj volumes/bunny.vdb --heatmap heat.ply "
       "--histogram hist.svg",
       "compare smaller shapes, or raise --tolerance", declareHausdorff, runHausdorff,
       outputsOfHausdorff});
}

}  // namespace d2vdb::cli
