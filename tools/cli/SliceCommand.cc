// d2vdb slice: iso-lines of a .vdb grid on an axis-aligned plane (marching squares) as SVG.
#include <filesystem>
#include <iomanip>
#include <optional>
#include <string>
#include <vector>

#include "Command.h"
#include "ContourInputs.h"
#include "d2vdb/contour/IsoLines.h"
#include "d2vdb/contour/IsoLinesSvg.h"
#include "d2vdb/contour/SliceMeasures.h"
#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/AtomicFileSet.h"

namespace d2vdb::cli {
namespace {

struct SliceArguments {
  std::string input, output, gridName, axis = "z", polylines;
  SliceOptions slice;
};

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

void declareSlice(CLI::App& command, SliceArguments& args) {
  command.add_option("input", args.input, "Input .vdb file")->required();
  command.add_option("output", args.output, "Output .svg file (written atomically)")->required();
  command.add_option("--axis", args.axis, "Normal of the plane: x, y or z")
      ->capture_default_str()
      ->check(CLI::IsMember({"x", "y", "z"}));
  command.add_option("--offset", args.slice.offset,
                     "World coordinate of the plane along the axis (default: the centre of the "
                     "grid's active voxels)");
  declareIsoAndGridOptions(command, args.slice.isoValue, args.gridName);
  command.add_option("--polylines", args.polylines,
                     "Also write the lines as JSON: {axis, offset, iso, plane_axes, polylines: "
                     "[{closed, points: [[u, v], ...]}]}");
}

// Warns when the slice has no line, or lines that leave the grid's stored band.
void warnAboutLines(const Slice& slice, const SliceLineCounts& counts) {
  if (counts.lines == 0) {
    warning("no iso-line on the plane " + std::string(axisName(slice.axis)) + " = " +
            std::to_string(slice.offset));
  } else if (counts.closedLines < counts.lines) {
    warning(std::to_string(counts.lines - counts.closedLines) +
            " iso-lines are open: they leave the grid's stored band");
  }
}

Report runSlice(const SliceArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  const openvdb::GridBase::Ptr grid = loadContourGrid(args.input, args.gridName, "slice");
  SliceOptions options = args.slice;
  options.axis = args.axis == "x" ? 0 : (args.axis == "y" ? 1 : 2);
  if (context.count("--offset") == 0) {
    options.offset = activeVoxelCenterOffset(*grid, options.axis).value_or(options.offset);
  }
  const Slice slice = sliceIsoLines(*grid, options);
  const SliceLineCounts counts = countSliceLines(slice);
  warnAboutLines(slice, counts);
  // Both outputs to temporary names; neither replaces its target unless both were written.
  AtomicFileSet files;
  files.stage(args.output, [&](const std::filesystem::path& temporary) {
    writeIsoLinesSvg(temporary.string(), slice);
  });
  if (!args.polylines.empty()) {
    const nlohmann::json lines = polylinesJson(slice, options.isoValue);
    files.stage(args.polylines, [&](const std::filesystem::path& temporary) {
      writeStreamAtomically(
          temporary, [&](std::ostream& out) { out << std::setprecision(17) << lines << '\n'; });
    });
  }
  files.commit();
  Report report;
  report.json = {
      {"input", args.input},
      {"output", args.output},
      {"grid", grid->getName()},
      {"axis", axisName(slice.axis)},
      {"offset", slice.offset},
      {"iso", options.isoValue},
      {"plane_axes", {axisName(slice.planeAxes[0]), axisName(slice.planeAxes[1])}},
      {"lines", counts.lines},
      {"closed_lines", counts.closedLines},
      {"points", counts.points},
      {"seconds", clock.seconds()},
  };
  report.text = "wrote " + args.output + ": " + std::to_string(counts.lines) + " iso-lines (" +
                std::to_string(counts.closedLines) + " closed), " + std::to_string(counts.points) +
                " points on the plane " + axisName(slice.axis) + " = " +
                std::to_string(slice.offset) + "\n";
  return report;
}

std::vector<OutputFile> outputsOfSlice(const SliceArguments& args) {
  return {{"output", args.output, OutputFormat::Svg},
          {"--polylines", args.polylines, OutputFormat::Json}};
}

}  // namespace

void addSliceCommand(CommandRegistry& registry) {
  registry.add<SliceArguments>(
      {"slice",
       "Draw the iso-lines of a grid in a .vdb file on an axis-aligned plane as SVG (marching\n"
       "squares; closed lines for a closed level set, inside on the left). The SVG shows the two\n"
       "other axes in cyclic order (z: x right, y up). --polylines also writes the lines as JSON.\n"
       "Example: d2vdb slice volumes/bunny.vdb bunny-z.svg --axis z --offset 0.1",
       "the level set is too large for this machine; mesh a coarser one", declareSlice, runSlice,
       outputsOfSlice});
}

}  // namespace d2vdb::cli
