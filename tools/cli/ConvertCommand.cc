// d2vdb convert: reads a level set from any .vdb file and writes it back with d2vdb's
// conventions (grid name, class, metadata, Blosc compression).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "Command.h"
#include "SharedOptions.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/DensityToLevelSet.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/VdbFile.h"

namespace d2vdb::cli {
namespace {

struct ConvertArguments {
  std::string input, output, gridName, outputName = "surface";
  std::optional<double> iso;  ///< rebuild the level set of this iso-surface
  double halfWidth = 3;       ///< of the rebuilt band
  VdbOutputArguments vdb;
};

void declareConvert(CLI::App& command, ConvertArguments& args) {
  command.add_option("input", args.input, "Input .vdb file")->required();
  command.add_option("output", args.output, "Output .vdb file (written atomically)")->required();
  command.add_option("--grid", args.gridName,
                     "Grid to read (default: the first level set, else the first float grid)");
  command.add_option("--name", args.outputName, "Name of the written grid")->capture_default_str();
  command.add_option("--iso", args.iso,
                     "Rebuild the level set of the iso-surface at this value (needed for a fog "
                     "volume / density grid, inside where the density exceeds it; for distances "
                     "an offset in world units)");
  command
      .add_option("--half-width", args.halfWidth,
                  "With --iso: narrow-band half-width of the rebuilt level set, in voxels")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  declareVdbOutputOptions(command, args.vdb);
}

Report runConvert(const ConvertArguments& args, const CommandContext&) {
  const Stopwatch clock;
  LoadOptions load;
  load.purpose = "the input of 'd2vdb convert'";
  load.gridName = args.gridName;
  openvdb::FloatGrid::Ptr grid = loadInputAs<LevelSetInput>(args.input, load).floatGrid();
  if (args.iso) {
    grid = levelSetOfIsoSurface(*grid, *args.iso, args.halfWidth);
  } else if (holdsDensity(*grid)) {
    throw InputError("grid '" + grid->getName() + "' of '" + args.input +
                     "' holds densities (a fog volume), not signed distances: give --iso VALUE "
                     "(e.g. --iso 0.5) to convert its iso-surface into a level set");
  }
  grid->setName(args.outputName);
  writeVdb(args.output, {grid},
           args.vdb.writeOptions(std::filesystem::path(args.input).filename().string()));
  Report report;
  report.json = {{"input", args.input},
                 {"output", args.output},
                 {"grid", args.outputName},
                 {"voxel_size", grid->voxelSize()[0]},
                 {"active_voxels", grid->activeVoxelCount()},
                 {"seconds", clock.seconds()}};
  report.text = "wrote " + args.output + " (" + std::to_string(grid->activeVoxelCount()) +
                " active voxels) in " + std::to_string(clock.seconds()) + " s\n";
  return report;
}

std::vector<OutputFile> outputsOfConvert(const ConvertArguments& args) {
  return {{"output", args.output, OutputFormat::Vdb}};
}

}  // namespace

void addConvertCommand(CommandRegistry& registry) {
  registry.add<ConvertArguments>(
      {"convert",
       "Read a level set from a .vdb file (written by d2vdb or any other OpenVDB tool) and write "
       "it with d2vdb's conventions: grid name 'surface', class level set, d2vdb metadata, "
       "Blosc. A fog volume (densities) becomes the level set of its iso-surface at --iso.\n"
       "Example: d2vdb convert volumes/bunny.vdb surface.vdb --grid surface\n"
       "         d2vdb convert volumes/smoke.vdb smoke-surface.vdb --grid density --iso 0.5",
       "the level set is too large for this machine; convert a coarser one", declareConvert,
       runConvert, outputsOfConvert});
}

}  // namespace d2vdb::cli
