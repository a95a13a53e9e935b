// d2vdb slice: iso-lines of a .vdb grid on an axis-aligned plane (marching squares) as SVG.
#include <filesystem>
#include <iomanip>
#include <string>

#include "Command.h"
#include "d2vdb/contour/IsoLines.h"
#include "d2vdb/contour/IsoLinesSvg.h"
#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/io/InputFile.h"

namespace d2vdb::cli {
namespace {

const char* axisName(int axis) {
  return axis == 0 ? "x" : (axis == 1 ? "y" : "z");
}

/// {"axis", "offset", "iso", "plane_axes", "polylines": [{"closed", "points": [[u, v], ...]}]}
nlohmann::json polylinesJson(const Slice& slice, double iso) {
  nlohmann::json lines = nlohmann::json::array();
  for (const IsoLine& line : slice.lines) {
    nlohmann::json points = nlohmann::json::array();
    for (const auto& point : line.points) points.push_back({point.x(), point.y()});
    lines.push_back({{"closed", line.closed}, {"points", points}});
  }
  return {{"axis", axisName(slice.axis)},
          {"offset", slice.offset},
          {"iso", iso},
          {"plane_axes", {axisName(slice.planeAxes[0]), axisName(slice.planeAxes[1])}},
          {"polylines", lines}};
}

}  // namespace

void addSliceCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  struct Arguments {
    std::string input, output, gridName, axis = "z", polylines;
    SliceOptions slice;
  };
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "slice",
      "Draw the iso-lines of a grid in a .vdb file on an axis-aligned plane as SVG (marching\n"
      "squares; closed lines for a closed level set, inside on the left). The SVG shows the two\n"
      "other axes in cyclic order (z: x right, y up). --polylines also writes the lines as JSON.\n"
      "Example: d2vdb slice bunny.vdb bunny-z.svg --axis z --offset 0.1");
  command->add_option("input", args->input, "Input .vdb file")->required();
  command->add_option("output", args->output, "Output .svg file (written atomically)")->required();
  command->add_option("--axis", args->axis, "Normal of the plane: x, y or z")
      ->capture_default_str()
      ->check(CLI::IsMember({"x", "y", "z"}));
  command->add_option("--offset", args->slice.offset,
                      "World coordinate of the plane along the axis (default: the centre of the "
                      "grid's active voxels)");
  command->add_option("--iso", args->slice.isoValue, "Iso-value (grid value units)")
      ->capture_default_str();
  command->add_option("--grid", args->gridName,
                      "Name of the grid (default: the first float/double level set)");
  command->add_option("--polylines", args->polylines,
                      "Also write the lines as JSON: {axis, offset, iso, plane_axes, polylines: "
                      "[{closed, points: [[u, v], ...]}]}");
  command->add_flag("--json", options.json, "Print the summary as JSON on stdout");

  registry.add(command, [args, &options, command]() {
    const Stopwatch clock;
    LoadOptions load;
    load.purpose = "the input of 'd2vdb slice'";
    load.gridName = args->gridName;
    load.gridTypes = ScalarGridTypes::FloatOrDouble;
    const openvdb::GridBase::Ptr grid = loadInputAs<LevelSetInput>(args->input, load).grid;
    args->slice.axis = args->axis == "x" ? 0 : (args->axis == "y" ? 1 : 2);
    if (command->count("--offset") == 0) {
      const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
      if (!box.empty()) {
        args->slice.offset = grid->indexToWorld(box.getCenter())[args->slice.axis];
      }
    }
    const Slice slice = sliceIsoLines(*grid, args->slice);
    std::size_t closed = 0, points = 0;
    for (const IsoLine& line : slice.lines) {
      closed += line.closed ? 1 : 0;
      points += line.points.size();
    }
    if (slice.lines.empty()) {
      warning("no iso-line on the plane " + std::string(axisName(slice.axis)) + " = " +
              std::to_string(slice.offset));
    } else if (closed < slice.lines.size()) {
      warning(std::to_string(slice.lines.size() - closed) +
              " iso-lines are open: they leave the grid's stored band");
    }
    writeIsoLinesSvg(args->output, slice);
    if (!args->polylines.empty()) {
      const nlohmann::json lines = polylinesJson(slice, args->slice.isoValue);
      writeStreamAtomically(args->polylines, [&](std::ostream& out) {
        out << std::setprecision(17) << lines << '\n';
      });
    }
    const nlohmann::json report = {
        {"input", args->input},
        {"output", args->output},
        {"grid", grid->getName()},
        {"axis", axisName(slice.axis)},
        {"offset", slice.offset},
        {"iso", args->slice.isoValue},
        {"plane_axes", {axisName(slice.planeAxes[0]), axisName(slice.planeAxes[1])}},
        {"lines", slice.lines.size()},
        {"closed_lines", closed},
        {"points", points},
        {"seconds", clock.seconds()},
    };
    if (options.json) {
      printJson(report);
    } else {
      status(options, "wrote " + args->output + ": " + std::to_string(slice.lines.size()) +
                          " iso-lines (" + std::to_string(closed) + " closed), " +
                          std::to_string(points) + " points on the plane " + axisName(slice.axis) +
                          " = " + std::to_string(slice.offset));
    }
    return kSuccess;
  });
}

// TRANSITION: the old registration until this command has its CommandDefinition.
void addSliceCommand(CommandRegistry& registry) {
  addSliceCommand(registry.app(), registry, registry.legacyOptions());
}

}  // namespace d2vdb::cli
