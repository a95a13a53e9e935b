// d2vdb convert: reads a level set from any .vdb file and writes it back with d2vdb's
// conventions (grid name, class, metadata, Blosc compression).
#include <filesystem>
#include <string>

#include "Command.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/VdbFile.h"

namespace d2vdb::cli {

void addConvertCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  struct Arguments {
    std::string input, output, gridName, outputName = "surface";
    bool half = false, noCompression = false;
  };
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "convert",
      "Read a level set from a .vdb file (written by d2vdb or any other OpenVDB tool) and write it "
      "with d2vdb's conventions: grid name 'surface', class level set, d2vdb metadata, Blosc.\n"
      "Example: d2vdb convert houdini_export.vdb surface.vdb --grid density");
  command->add_option("input", args->input, "Input .vdb file")->required();
  command->add_option("output", args->output, "Output .vdb file (written atomically)")->required();
  command->add_option("--grid", args->gridName,
                      "Grid to read (default: the first level set, else the first float grid)");
  command->add_option("--name", args->outputName, "Name of the written grid")
      ->capture_default_str();
  command->add_flag("--half", args->half, "Store values as 16-bit half floats (smaller, lossy)");
  command->add_flag("--no-compression", args->noCompression, "Write without Blosc compression");

  registry.add(command, [args, &options]() {
    const Stopwatch clock;
    LoadOptions load;
    load.purpose = "the input of 'd2vdb convert'";
    load.gridName = args->gridName;
    const openvdb::FloatGrid::Ptr grid = loadInputAs<LevelSetInput>(args->input, load).floatGrid();
    grid->setName(args->outputName);
    VdbWriteOptions writeOptions;
    writeOptions.blosc = !args->noCompression;
    writeOptions.halfFloat = args->half;
    writeOptions.source = std::filesystem::path(args->input).filename().string();
    writeVdb(args->output, {grid}, writeOptions);
    status(options, "wrote " + args->output + " (" + std::to_string(grid->activeVoxelCount()) +
                        " active voxels) in " + std::to_string(clock.seconds()) + " s");
    return kSuccess;
  });
}

}  // namespace d2vdb::cli
