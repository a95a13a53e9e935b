// d2vdb hausdorff: the exact Hausdorff distance between two B-spline curves (Chen et al. 2010),
// both one-sided distances with their pairs and certified brackets, optionally drawn as SVG.
#include <algorithm>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "Command.h"
#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/measure/CurveHausdorff.h"

namespace d2vdb::cli {
namespace {

nlohmann::json pointJson(const Eigen::Vector3d& point, int dimension) {
  if (dimension == 2) return {point.x(), point.y()};
  return {point.x(), point.y(), point.z()};
}

const char* caseName(HausdorffCase pairCase) {
  switch (pairCase) {
    case HausdorffCase::EndPoints:
      return "end points";
    case HausdorffCase::EndPointAndInterior:
      return "end point and interior point";
    case HausdorffCase::MutuallyOrthogonal:
      return "mutually orthogonal interior points";
    case HausdorffCase::Bisector:
      return "bisector (several nearest points)";
  }
  return "";
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
          {"case_name", caseName(result.pairCase)},
          {"converged", result.converged},
          {"intervals", result.intervalsExamined},
          {"depth", result.deepestLevel}};
}

std::string oneSidedText(const std::string& name, const OneSidedHausdorff& result) {
  std::ostringstream text;
  text.precision(15);
  text << "  " << name << " = " << result.distance << "  bracket [" << result.lowerBound << ", "
       << result.upperBound << "]\n"
       << "    pair u = " << result.fromParameter << " (" << result.fromPoint.x() << ", "
       << result.fromPoint.y() << ", " << result.fromPoint.z() << "), v = " << result.toParameter
       << " (" << result.toPoint.x() << ", " << result.toPoint.y() << ", " << result.toPoint.z()
       << "), case " << static_cast<int>(result.pairCase) << ": " << caseName(result.pairCase)
       << '\n';
  return text.str();
}

// Both curves as polylines, their control polygons, and the Hausdorff pair as a segment with its
// two points, projected onto the xy plane (y up).
void writeSvg(const std::string& file, const BSplineCurve& a, const BSplineCurve& b,
              const OneSidedHausdorff& pair) {
  const std::size_t segments = std::max(a.toBezierSegments().size(), b.toBezierSegments().size());
  const int samples = static_cast<int>(std::clamp<std::size_t>(64 * segments, 512, 20000));
  const std::vector<Eigen::Vector3d> pointsA = a.sample(samples);
  const std::vector<Eigen::Vector3d> pointsB = b.sample(samples);
  Eigen::AlignedBox3d box;
  for (const auto* points : {&pointsA, &pointsB, &a.controlPoints(), &b.controlPoints()}) {
    for (const Eigen::Vector3d& point : *points) box.extend(point);
  }
  const double extent = std::max({box.sizes().x(), box.sizes().y(), 1e-300});
  const double margin = 0.05 * extent;
  const double width = box.sizes().x() + 2.0 * margin;
  const double height = box.sizes().y() + 2.0 * margin;
  const double stroke = 0.004 * extent;
  const auto x = [&](const Eigen::Vector3d& point) { return point.x() - box.min().x() + margin; };
  const auto y = [&](const Eigen::Vector3d& point) { return box.max().y() - point.y() + margin; };
  const auto polyline = [&](const std::vector<Eigen::Vector3d>& points, const char* colour,
                            double strokeWidth, const char* extra) {
    std::ostringstream text;
    text.precision(12);
    text << "  <polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"" << strokeWidth
         << "\"" << extra << " points=\"";
    for (const Eigen::Vector3d& point : points) text << x(point) << ',' << y(point) << ' ';
    text << "\"/>\n";
    return text.str();
  };
  writeStreamAtomically(file, [&](std::ostream& out) {
    out.precision(12);
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << width << ' ' << height
        << "\" width=\"800\" height=\"" << 800.0 * height / width << "\">\n"
        << "  <!-- d2vdb hausdorff: curve A (blue), curve B (red), control polygons (thin), "
           "Hausdorff pair (black); 3D curves are drawn projected onto the xy plane -->\n"
        << polyline(a.controlPoints(), "#9db4d8", 0.5 * stroke, " stroke-dasharray=\"4 3\"")
        << polyline(b.controlPoints(), "#e0a8a8", 0.5 * stroke, " stroke-dasharray=\"4 3\"")
        << polyline(pointsA, "#1f4e9c", stroke, "") << polyline(pointsB, "#b3261e", stroke, "")
        << "  <line x1=\"" << x(pair.fromPoint) << "\" y1=\"" << y(pair.fromPoint) << "\" x2=\""
        << x(pair.toPoint) << "\" y2=\"" << y(pair.toPoint) << "\" stroke=\"black\" stroke-width=\""
        << stroke << "\"/>\n";
    for (const Eigen::Vector3d& point : {pair.fromPoint, pair.toPoint}) {
      out << "  <circle cx=\"" << x(point) << "\" cy=\"" << y(point) << "\" r=\"" << 2.5 * stroke
          << "\" fill=\"black\"/>\n";
    }
    out << "</svg>\n";
  });
}

}  // namespace

void addHausdorffCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  struct Arguments {
    std::string a, b, svg;
    bool oneSided = false;
    HausdorffOptions hausdorff;
  };
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "hausdorff",
      "Exact Hausdorff distance between two B-spline curves (.json, 2D or 3D, any degree): "
      "H(A, B) = max(h(A -> B), h(B -> A)) with h(A -> B) = max over A of the distance to B. "
      "Reports both one-sided distances, the Hausdorff pairs (parameters and points), which of the "
      "four cases of Chen et al. (2010) each pair is, and the certified bracket [lower, upper].\n"
      "Example: d2vdb hausdorff a.json b.json --svg pair.svg --json");
  command->add_option("a", args->a, "First curve (.json)")->required();
  command->add_option("b", args->b, "Second curve (.json)")->required();
  command->add_flag("--one-sided", args->oneSided, "Only h(A -> B)");
  command->add_option("--svg", args->svg,
                      "Draw both curves and the Hausdorff pair into this SVG file (xy plane)");
  command
      ->add_option("--tolerance", args->hausdorff.relativeTolerance,
                   "Bracket width relative to the size of the two curves (1e-15 to 0.1)")
      ->capture_default_str()
      ->check(CLI::Range(1e-15, 0.1));
  command
      ->add_option("--max-depth", args->hausdorff.maxDepth,
                   "Bound on the halvings of one knot span (then the bracket reached is reported)")
      ->capture_default_str()
      ->check(CLI::Range(1, 200));
  command->add_flag("--json", options.json, "Print one JSON document on stdout");

  registry.add(command, [args, &options]() {
    const Stopwatch clock;
    LoadOptions load;
    load.purpose = "each curve given to 'd2vdb hausdorff'";
    const BSplineCurve a = loadInputAs<BSplineCurve>(args->a, load);
    const BSplineCurve b = loadInputAs<BSplineCurve>(args->b, load);
    HausdorffDistance result;
    if (args->oneSided) {
      result.aToB = oneSidedHausdorff(a, b, args->hausdorff);
      result.distance = result.aToB.distance;
      result.lowerBound = result.aToB.lowerBound;
      result.upperBound = result.aToB.upperBound;
      result.aToBIsLarger = true;
    } else {
      result = hausdorffDistance(a, b, args->hausdorff);
    }
    const OneSidedHausdorff& pair = result.aToBIsLarger ? result.aToB : result.bToA;
    std::vector<std::string> warnings = result.aToB.warnings;
    if (!args->oneSided) {
      warnings.insert(warnings.end(), result.bToA.warnings.begin(), result.bToA.warnings.end());
    }
    for (const std::string& message : warnings) warning(message);
    if (!args->svg.empty()) writeSvg(args->svg, a, b, pair);

    nlohmann::json report = {
        {"a", args->a},
        {"b", args->b},
        {"one_sided", args->oneSided},
        {"distance", result.distance},
        {"lower_bound", result.lowerBound},
        {"upper_bound", result.upperBound},
        {"larger_direction", result.aToBIsLarger ? "a_to_b" : "b_to_a"},
        {"relative_tolerance", args->hausdorff.relativeTolerance},
        {"converged", result.aToB.converged && (args->oneSided || result.bToA.converged)},
        {"a_to_b", oneSidedJson(result.aToB, a.dimension(), b.dimension())},
        {"seconds", clock.seconds()},
        {"warnings", warnings},
    };
    if (!args->oneSided) report["b_to_a"] = oneSidedJson(result.bToA, b.dimension(), a.dimension());
    if (!args->svg.empty()) report["svg"] = args->svg;
    if (options.json) {
      printJson(report);
      return kSuccess;
    }
    std::cout.precision(15);
    std::cout << (args->oneSided ? "one-sided Hausdorff distance h(A -> B) = "
                                 : "Hausdorff distance H(A, B) = ")
              << result.distance << "  bracket [" << result.lowerBound << ", " << result.upperBound
              << "]\n"
              << oneSidedText("h(A -> B)", result.aToB);
    if (!args->oneSided) std::cout << oneSidedText("h(B -> A)", result.bToA);
    if (!args->svg.empty()) status(options, "wrote " + args->svg);
    return kSuccess;
  });
}

}  // namespace d2vdb::cli
