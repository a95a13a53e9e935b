// d2vdb mesh: iso-surface of a .vdb grid to a triangle mesh (marching cubes), optionally checked.
#include <optional>
#include <string>
#include <vector>

#include "Command.h"
#include "ContourInputs.h"
#include "JsonReports.h"
#include "ReportText.h"
#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/MeshGenus.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/MeshValidation.h"

namespace d2vdb::cli {
namespace {

struct MeshArguments {
  std::string input, output, gridName;
  IsoSurfaceOptions surface;
  bool check = false, noNormals = false;
};

void declareMesh(CLI::App& command, MeshArguments& args) {
  command.add_option("input", args.input, "Input .vdb file")->required();
  command.add_option("output", args.output, "Output mesh (.obj, .ply, .stl; written atomically)")
      ->required();
  declareIsoAndGridOptions(command, args.surface.isoValue, args.gridName);
  command.add_flag("--check", args.check,
                   "Validate the mesh: closed, manifold, oriented, Euler characteristic, genus");
  command.add_flag("--raw", args.surface.raw,
                   "Exact edge interpolation even at grid points (may give zero-area triangles)");
  command.add_flag("--no-normals", args.noNormals, "Do not write vertex normals");
}

// The "check" report of --check (the mesh report with its genus), its summary line printed now
// (before the warning of a failed check), and the exit code: kRunFailure unless the mesh is
// closed, manifold and oriented.
int checkMesh(const TriangleMesh& mesh, const CommandContext& context, nlohmann::json& report) {
  const MeshReport check = validateMesh(mesh);
  const std::optional<long> genus = surfaceGenus(check);
  nlohmann::json checkJson = meshReportJson(check);
  checkJson["genus"] = genus ? nlohmann::json(*genus) : nlohmann::json(nullptr);
  report["check"] = checkJson;
  const auto yesNo = [](bool value) { return value ? "yes" : "no"; };
  printSummaryLineNow(context, std::string("check: closed ") + yesNo(check.closed) + ", manifold " +
                                   yesNo(check.manifold) + ", oriented " + yesNo(check.oriented) +
                                   ", Euler characteristic " +
                                   std::to_string(check.eulerCharacteristic) + ", " +
                                   std::to_string(check.connectedComponentCount) + " components" +
                                   (genus ? ", genus " + std::to_string(*genus) : ""));
  if (!isClosedOrientedManifold(check)) {
    warning("the mesh failed the check: " + check.problems());
    return kRunFailure;
  }
  return kSuccess;
}

Report runMesh(const MeshArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  const openvdb::GridBase::Ptr grid = loadContourGrid(args.input, args.gridName, "mesh");
  IsoSurfaceOptions surface = args.surface;
  surface.computeNormals = !args.noNormals;
  const Stopwatch extraction;
  const TriangleMesh mesh = extractIsoSurface(*grid, surface, context.progress());
  const double extractionSeconds = extraction.seconds();
  if (mesh.triangles.empty()) {
    throw InputError("grid '" + grid->getName() + "' of " + args.input +
                     " has no surface at iso-value " + std::to_string(surface.isoValue) +
                     ": no stored value lies on the other side of it");
  }
  writeMesh(args.output, mesh);

  Report report;
  report.json = {
      {"input", args.input},
      {"output", args.output},
      {"grid", grid->getName()},
      {"iso", surface.isoValue},
      {"vertices", mesh.vertexCount()},
      {"triangles", mesh.triangleCount()},
      {"extraction_seconds", extractionSeconds},
      {"seconds", clock.seconds()},
  };
  if (args.check) report.exitCode = checkMesh(mesh, context, report.json);
  report.text = "wrote " + args.output + ": " + std::to_string(mesh.vertexCount()) + " vertices, " +
                std::to_string(mesh.triangleCount()) + " triangles, " +
                std::to_string(clock.seconds()) + " s\n";
  return report;
}

std::vector<OutputFile> outputsOfMesh(const MeshArguments& args) {
  return {{"output", args.output, OutputFormat::Mesh}};
}

}  // namespace

void addMeshCommand(CommandRegistry& registry) {
  registry.add<MeshArguments>(
      {"mesh",
       "Extract the iso-surface of a grid in a .vdb file as a triangle mesh (.obj, .ply, .stl) by\n"
       "marching cubes: closed, 2-manifold and outward-oriented for a closed level set, with one\n"
       "shared vertex per crossed edge and normals from the grid gradient.\n"
       "--iso offsets a level set (world units, + outward); |iso| must stay a voxel inside the "
       "band.\n"
       "With --check the mesh is validated; the exit code is 3 if it is not closed, manifold and "
       "oriented.\n"
       "Example: d2vdb mesh volumes/bunny.vdb bunny.obj --check",
       "the level set is too large for this machine; mesh a coarser one", declareMesh, runMesh,
       outputsOfMesh});
}

}  // namespace d2vdb::cli
