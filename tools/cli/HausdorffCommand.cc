// d2vdb hausdorff: the exact Hausdorff distance between two B-spline curves (Chen et al. 2010),
// both one-sided distances with their pairs and certified brackets, optionally drawn as SVG.
#include <sstream>
#include <string>
#include <vector>

#include "Command.h"
#include "JsonReports.h"
#include "ReportText.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/measure/CurveHausdorff.h"
#include "d2vdb/plot/SvgCanvas.h"
#include "d2vdb/spline/CurvePolyline.h"

namespace d2vdb::cli {
namespace {

struct HausdorffArguments {
  std::string a, b, svg;
  bool oneSided = false;
  HausdorffOptions hausdorff;
};

/// Significant digits of the text report.
constexpr int kDistanceDigits = 15;

void declareHausdorff(CLI::App& command, HausdorffArguments& args) {
  command.add_option("a", args.a, "First curve (.json)")->required();
  command.add_option("b", args.b, "Second curve (.json)")->required();
  command.add_flag("--one-sided", args.oneSided, "Only h(A -> B)");
  command.add_option("--svg", args.svg,
                     "Draw both curves and the Hausdorff pair into this SVG file (xy plane)");
  command
      .add_option("--tolerance", args.hausdorff.relativeTolerance,
                  "Bracket width relative to the size of the two curves (1e-15 to 0.1)")
      ->capture_default_str()
      ->check(CLI::Range(1e-15, 0.1));
  command
      .add_option("--max-depth", args.hausdorff.maxDepth,
                  "Bound on the halvings of one knot span (then the bracket reached is reported)")
      ->capture_default_str()
      ->check(CLI::Range(1, 200));
}

// H(a, b), or with --one-sided h(a -> b) alone as the larger direction (bToA stays empty).
HausdorffDistance computeDistance(const HausdorffArguments& args, const BSplineCurve& a,
                                  const BSplineCurve& b) {
  if (!args.oneSided) return hausdorffDistance(a, b, args.hausdorff);
  HausdorffDistance result;
  result.aToB = oneSidedHausdorff(a, b, args.hausdorff);
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

nlohmann::json hausdorffJson(const HausdorffArguments& args, const BSplineCurve& a,
                             const BSplineCurve& b, const HausdorffDistance& result,
                             const std::vector<std::string>& warnings, double seconds) {
  nlohmann::json report = {
      {"a", args.a},
      {"b", args.b},
      {"one_sided", args.oneSided},
      {"distance", result.distance},
      {"lower_bound", result.lowerBound},
      {"upper_bound", result.upperBound},
      {"larger_direction", result.aToBIsLarger ? "a_to_b" : "b_to_a"},
      {"relative_tolerance", args.hausdorff.relativeTolerance},
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

Report runHausdorff(const HausdorffArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  LoadOptions load;
  load.purpose = "each curve given to 'd2vdb hausdorff'";
  const BSplineCurve a = loadInputAs<BSplineCurve>(args.a, load);
  const BSplineCurve b = loadInputAs<BSplineCurve>(args.b, load);
  const HausdorffDistance result = computeDistance(args, a, b);
  std::vector<std::string> warnings = result.aToB.warnings;
  if (!args.oneSided) {
    warnings.insert(warnings.end(), result.bToA.warnings.begin(), result.bToA.warnings.end());
  }
  for (const std::string& message : warnings) warning(message);
  if (!args.svg.empty()) {
    writeSvg(args.svg, a, b, result.aToBIsLarger ? result.aToB : result.bToA);
    printSummaryLineNow(context, "wrote " + args.svg);
  }
  return {hausdorffJson(args, a, b, result, warnings, clock.seconds()), hausdorffText(args, result),
          Report::Text::Answer};
}

std::vector<OutputFile> outputsOfHausdorff(const HausdorffArguments& args) {
  return {{"--svg", args.svg, OutputFormat::Svg}};
}

}  // namespace

void addHausdorffCommand(CommandRegistry& registry) {
  registry.add<HausdorffArguments>(
      {"hausdorff",
       "Exact Hausdorff distance between two B-spline curves (.json, 2D or 3D, any degree): "
       "H(A, B) = max(h(A -> B), h(B -> A)) with h(A -> B) = max over A of the distance to B. "
       "Reports both one-sided distances, the Hausdorff pairs (parameters and points), which of "
       "the four cases of Chen et al. (2010) each pair is, and the certified bracket [lower, "
       "upper].\n"
       "Example: d2vdb hausdorff fitted.json volumes/helix.json --svg pair.svg --json",
       "compare curves with fewer control points, or raise --tolerance", declareHausdorff,
       runHausdorff, outputsOfHausdorff});
}

}  // namespace d2vdb::cli
