// d2vdb project: the nearest point of a B-spline curve to a given point, and every local extremum
// of the distance along the curve (point–curve projection by Bézier root isolation).
#include <sstream>
#include <string>

#include "Command.h"
#include "JsonReports.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/measure/PointProjection.h"

namespace d2vdb::cli {
namespace {

struct ProjectArguments {
  std::string curve;
  double x = 0.0, y = 0.0, z = 0.0;
};

/// Significant digits of the text report.
constexpr int kProjectionDigits = 15;

const char* kindName(ExtremumKind kind) {
  switch (kind) {
    case ExtremumKind::Minimum:
      return "minimum";
    case ExtremumKind::Maximum:
      return "maximum";
    case ExtremumKind::Degenerate:
      return "degenerate";
  }
  return "degenerate";
}

void declareProject(CLI::App& command, ProjectArguments& args) {
  command.add_option("curve", args.curve, "B-spline curve file (.json)")->required();
  command.add_option("x", args.x, "X coordinate of the point")->required();
  command.add_option("y", args.y, "Y coordinate of the point")->required();
  command.add_option("z", args.z, "Z coordinate of the point (default 0)");
}

nlohmann::json projectionJson(const ProjectArguments& args, const Eigen::Vector3d& point,
                              const PointProjection& projection, int dimension) {
  nlohmann::json extrema = nlohmann::json::array();
  for (const CurveExtremum& extremum : projection.extrema) {
    extrema.push_back({{"parameter", extremum.parameter},
                       {"point", pointJson(extremum.point, dimension)},
                       {"distance", extremum.distance},
                       {"kind", kindName(extremum.kind)},
                       {"end_point", extremum.atEndPoint}});
  }
  return {
      {"curve", args.curve},
      {"query", {point.x(), point.y(), point.z()}},
      {"parameter", projection.parameter},
      {"point", pointJson(projection.point, dimension)},
      {"distance", projection.distance},
      {"extrema", extrema},
  };
}

std::string projectionText(const PointProjection& projection, int dimension) {
  std::ostringstream text;
  text.precision(kProjectionDigits);
  text << "nearest point " << formatPoint(projection.point, kProjectionDigits, dimension)
       << " at t = " << projection.parameter << ", distance " << projection.distance << '\n'
       << "local extrema of the distance (" << projection.extrema.size() << "):\n";
  for (const CurveExtremum& extremum : projection.extrema) {
    text << "  t = " << extremum.parameter << "  " << kindName(extremum.kind) << "  distance "
         << extremum.distance << "  at "
         << formatPoint(extremum.point, kProjectionDigits, dimension)
         << (extremum.atEndPoint ? "  (end point)" : "") << '\n';
  }
  return text.str();
}

Report runProject(const ProjectArguments& args, const CommandContext&) {
  LoadOptions load;
  load.purpose = "the curve given to 'd2vdb project'";
  const BSplineCurve curve = loadInputAs<BSplineCurve>(args.curve, load);
  const Eigen::Vector3d point(args.x, args.y, args.z);
  const PointProjection projection = projectPoint(curve, point);
  return {projectionJson(args, point, projection, curve.dimension()),
          projectionText(projection, curve.dimension()), Report::Text::Answer};
}

}  // namespace

void addProjectCommand(CommandRegistry& registry) {
  registry.add<ProjectArguments>(
      {"project",
       "Project a point onto a B-spline curve (.json): the nearest point with its parameter and "
       "distance, and every local minimum and maximum of the distance along the curve (interior "
       "solutions of (C(t) - p) . C'(t) = 0, corners at knots, the ends of open curves). Z "
       "defaults to 0 (the plane of 2D curves).\n"
       "Example: d2vdb project volumes/helix.json 0 0 0.5 --json",
       "the input is too large for this machine", declareProject, runProject});
}

}  // namespace d2vdb::cli
