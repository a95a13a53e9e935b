// d2vdb mesh: iso-surface of a .vdb grid to a triangle mesh (marching cubes), optionally checked.
#include <filesystem>
#include <string>

#include "Command.h"
#include "JsonReports.h"
#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/MeshValidation.h"

namespace d2vdb::cli {

void addMeshCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  struct Arguments {
    std::string input, output, gridName;
    IsoSurfaceOptions surface;
    bool check = false, noNormals = false;
  };
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "mesh",
      "Extract the iso-surface of a grid in a .vdb file as a triangle mesh (.obj, .ply, .stl) by\n"
      "marching cubes: closed, 2-manifold and outward-oriented for a closed level set, with one\n"
      "shared vertex per crossed edge and normals from the grid gradient.\n"
      "--iso offsets a level set (world units, + outward); |iso| must stay a voxel inside the "
      "band.\n"
      "With --check the mesh is validated; the exit code is 3 if it is not closed, manifold and "
      "oriented.\n"
      "Example: d2vdb mesh bunny.vdb bunny.obj --check");
  command->add_option("input", args->input, "Input .vdb file")->required();
  command->add_option("output", args->output, "Output mesh (.obj, .ply, .stl; written atomically)")
      ->required();
  command->add_option("--iso", args->surface.isoValue, "Iso-value (grid value units)")
      ->capture_default_str();
  command->add_option("--grid", args->gridName,
                      "Name of the grid (default: the first float/double level set)");
  command->add_flag("--check", args->check,
                    "Validate the mesh: closed, manifold, oriented, Euler characteristic, genus");
  command->add_flag("--raw", args->surface.raw,
                    "Exact edge interpolation even at grid points (may give zero-area triangles)");
  command->add_flag("--no-normals", args->noNormals, "Do not write vertex normals");
  command->add_flag("--json", options.json, "Print the summary as JSON on stdout");

  registry.add(command, [args, &options]() {
    const Stopwatch clock;
    meshFormatFromPath(args->output);  // reject an unsupported extension before working
    LoadOptions load;
    load.purpose = "the input of 'd2vdb mesh'";
    load.gridName = args->gridName;
    load.gridTypes = ScalarGridTypes::FloatOrDouble;
    const openvdb::GridBase::Ptr grid = loadInputAs<LevelSetInput>(args->input, load).grid;
    args->surface.computeNormals = !args->noNormals;
    const Stopwatch extraction;
    const TriangleMesh mesh = extractIsoSurface(*grid, args->surface, makeProgressPrinter(options));
    const double extractionSeconds = extraction.seconds();
    if (mesh.triangles.empty()) {
      throw InputError("grid '" + grid->getName() + "' of " + args->input +
                       " has no surface at iso-value " + std::to_string(args->surface.isoValue) +
                       ": no stored value lies on the other side of it");
    }
    writeMesh(args->output, mesh);

    nlohmann::json report = {
        {"input", args->input},
        {"output", args->output},
        {"grid", grid->getName()},
        {"iso", args->surface.isoValue},
        {"vertices", mesh.vertexCount()},
        {"triangles", mesh.triangleCount()},
        {"extraction_seconds", extractionSeconds},
        {"seconds", clock.seconds()},
    };
    bool valid = true;
    if (args->check) {
      const MeshReport check = validateMesh(mesh);
      valid = check.closed && check.manifold && check.oriented;
      nlohmann::json checkJson = meshReportJson(check);
      // Total genus of a closed orientable surface: sum over components of (2 - chi_i) / 2.
      const long twiceGenus =
          2 * static_cast<long>(check.connectedComponentCount) - check.eulerCharacteristic;
      checkJson["genus"] = valid ? nlohmann::json(twiceGenus / 2) : nlohmann::json(nullptr);
      report["check"] = checkJson;
      if (!options.json) {
        const auto yesNo = [](bool value) { return value ? "yes" : "no"; };
        status(options, std::string("check: closed ") + yesNo(check.closed) + ", manifold " +
                            yesNo(check.manifold) + ", oriented " + yesNo(check.oriented) +
                            ", Euler characteristic " + std::to_string(check.eulerCharacteristic) +
                            ", " + std::to_string(check.connectedComponentCount) + " components" +
                            (valid ? ", genus " + std::to_string(twiceGenus / 2) : ""));
      }
      if (!valid) warning("the mesh failed the check: " + check.problems());
    }
    if (options.json) {
      printJson(report);
    } else {
      status(options, "wrote " + args->output + ": " + std::to_string(mesh.vertexCount()) +
                          " vertices, " + std::to_string(mesh.triangleCount()) + " triangles, " +
                          std::to_string(clock.seconds()) + " s");
    }
    return valid ? kSuccess : kRunFailure;
  });
}

// TRANSITION: the old registration until this command has its CommandDefinition.
void addMeshCommand(CommandRegistry& registry) {
  addMeshCommand(registry.app(), registry, registry.legacyOptions());
}

}  // namespace d2vdb::cli
