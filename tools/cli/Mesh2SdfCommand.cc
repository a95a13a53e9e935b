// d2vdb mesh2sdf: triangle mesh (OBJ/PLY/STL) to a narrow-band signed (or unsigned) distance field.
#include <filesystem>
#include <string>

#include "Command.h"
#include "JsonReports.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshMeasures.h"

namespace d2vdb::cli {

void addMesh2SdfCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  struct Arguments {
    std::string input, output, gridName;
    LevelSetOptions levelSet;
    bool half = false, noCompression = false, openVdbSigns = false;
  };
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "mesh2sdf",
      "Convert a triangle mesh (.obj, .ply, .stl) into a narrow-band level set (.vdb).\n"
      "Every band voxel's sign is checked exactly (closest-feature pseudonormals, else generalised "
      "winding numbers) and OpenVDB's wrong ones are corrected. Meshes with holes, non-manifold "
      "edges or flipped triangles still give a signed field (with a warning); use --unsigned for "
      "open surfaces such as sheets or cloth.\n"
      "Example: d2vdb mesh2sdf volumes/bunny.obj bunny.vdb --resolution 256");
  command->add_option("input", args->input, "Input mesh (.obj, .ply, .stl)")->required();
  command->add_option("output", args->output, "Output .vdb file (written atomically)")->required();
  auto* voxelSize = command->add_option("--voxel-size", args->levelSet.voxelSize,
                                        "Voxel edge length in world units");
  auto* resolution = command->add_option(
      "--resolution", args->levelSet.resolution,
      "Voxels along the longest side of the mesh's bounding box (instead of --voxel-size)");
  voxelSize->excludes(resolution)->check(positiveNumber());
  resolution->excludes(voxelSize)->check(positiveNumber());
  command->add_option("--half-width", args->levelSet.halfWidth, "Narrow-band half-width in voxels")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  command->add_flag("--unsigned", args->levelSet.unsignedDistance,
                    "Unsigned distance field (for open surfaces)");
  command->add_flag("--openvdb-signs", args->openVdbSigns,
                    "Keep OpenVDB's signs unchecked (faster; can be wrong next to sharp concave "
                    "corners and across holes)");
  command
      ->add_option("--max-voxels", args->levelSet.maxActiveVoxels,
                   "Refuse when the estimated number of active voxels exceeds this")
      ->capture_default_str();
  command->add_option("--name", args->gridName,
                      "Name of the written grid (default: surface, or unsigned_distance)");
  command->add_flag("--half", args->half, "Store values as 16-bit half floats (smaller, lossy)");
  command->add_flag("--no-compression", args->noCompression, "Write without Blosc compression");
  command->add_flag("--json", options.json, "Print the summary as JSON on stdout");

  registry.add(command, [args, &options, command]() {
    if (command->count("--voxel-size") + command->count("--resolution") == 0) {
      throw CLI::RequiredError("one of --voxel-size or --resolution");
    }
    const Stopwatch clock;
    LoadOptions load;
    load.purpose = "the input of 'd2vdb mesh2sdf'";
    const TriangleMesh mesh = loadInputAs<MeshInput>(args->input, load).mesh;
    status(options, "read " + args->input + ": " + std::to_string(mesh.vertexCount()) +
                        " vertices, " + std::to_string(mesh.triangleCount()) + " triangles");
    args->levelSet.exactSigns = !args->openVdbSigns;
    const LevelSetResult result =
        meshToLevelSet(mesh, args->levelSet, makeProgressPrinter(options));
    for (const std::string& message : result.warnings) warning(message);
    checkResolvesShape(*result.grid, boundingBox(mesh).extent().maxCoeff(), "the mesh");
    if (!args->gridName.empty()) result.grid->setName(args->gridName);

    VdbWriteOptions writeOptions;
    writeOptions.blosc = !args->noCompression;
    writeOptions.halfFloat = args->half;
    writeOptions.source = std::filesystem::path(args->input).filename().string();
    writeOptions.halfWidth = args->levelSet.halfWidth;
    writeVdb(args->output, {result.grid}, writeOptions);

    nlohmann::json report = {
        {"input", args->input},
        {"output", args->output},
        {"voxel_size", result.grid->voxelSize()[0]},
        {"half_width", args->levelSet.halfWidth},
        {"signed", !args->levelSet.unsignedDistance},
        {"active_voxels", result.grid->activeVoxelCount()},
        {"seconds", clock.seconds()},
        {"mesh", meshReportJson(result.meshReport)},
        {"signs", signReportJson(result.signs)},
        {"warnings", result.warnings},
    };
    if (options.json) {
      printJson(report);
    } else {
      if (result.signs.method != SignMethod::none) {
        status(options, std::string("signs checked by ") + signMethodName(result.signs.method) +
                            ": " + std::to_string(result.signs.correctedVoxels) +
                            " voxels of OpenVDB's conversion corrected");
      }
      status(options,
             "wrote " + args->output + ": " + std::to_string(result.grid->activeVoxelCount()) +
                 " active voxels, voxel size " + std::to_string(result.grid->voxelSize()[0]) +
                 ", " + std::to_string(clock.seconds()) + " s");
    }
    return kSuccess;
  });
}

}  // namespace d2vdb::cli
