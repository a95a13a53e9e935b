// d2vdb field: the squared-distance approximant field of a mesh, a level set, a point set, a
// B-spline curve or a polyline, written as one .vdb file (FieldFile.h).
#include <filesystem>
#include <string>
#include <vector>

#include "Command.h"
#include "FieldReports.h"
#include "JsonReports.h"
#include "ReportText.h"
#include "SharedOptions.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/FieldFromInput.h"
#include "d2vdb/io/InputFile.h"

namespace d2vdb::cli {
namespace {

struct FieldArguments {
  std::string input, output;
  BandArguments band;
  double padding = 0.5;
  VdbOutputArguments vdb;
  std::string smooth;  ///< "", "loop" or "pn": build a mesh's field from its smooth surface
};

void declareField(CLI::App& command, FieldArguments& args) {
  command.add_option("input", args.input, "Target file (mesh, .vdb, .xyz, curve .json)")
      ->required();
  command.add_option("output", args.output, "Output .vdb file (written atomically)")->required();
  declareBandOptions(command, args.band, {"the target", ""});
  command
      .add_option("--padding", args.padding,
                  "Working domain: the target's bounding box padded on every side by this "
                  "fraction of its largest side")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  declareVdbOutputOptions(command, args.vdb);
  command
      .add_option("--smooth", args.smooth,
                  "Meshes: the field of the mesh's smooth (C-infinity) surface, every band "
                  "voxel projected onto it (source: loop, the default, or pn)")
      ->expected(0, 1)
      ->default_str("loop")
      ->check(CLI::IsMember({"loop", "pn"}));
}

// Reads the input; --smooth takes meshes only, refused before anything else is built.
LoadedInput loadFieldInput(const FieldArguments& args, const FieldBuildOptions& build) {
  LoadOptions load;
  load.purpose = "the input of 'd2vdb field'";
  load.field = build.field;
  load.progress = build.progress;
  if (build.smooth) {
    load.purpose = "the input of 'd2vdb field --smooth' (the field of a mesh's smooth surface)";
    return loadInput(args.input, {InputKind::Mesh}, load);
  }
  return loadInput(args.input,
                   {InputKind::Mesh, InputKind::PointSet, InputKind::Field, InputKind::Curve,
                    InputKind::Polylines, InputKind::Surface},
                   load);
}

// "read X: N vertices, M triangles" for meshes, "read X: N points" for point sets.
void reportRead(const LoadedInput& input, const std::string& name, const CommandContext& context) {
  if (const auto* mesh = std::get_if<MeshInput>(&input.value)) {
    context.status("read " + name + ": " + std::to_string(mesh->mesh.vertexCount()) +
                   " vertices, " + std::to_string(mesh->mesh.triangleCount()) + " triangles");
  } else if (const auto* points = std::get_if<PointSetInput>(&input.value)) {
    context.status("read " + name + ": " + std::to_string(points->points.size()) + " points");
  }
}

FieldBuildOptions fieldBuildOptions(const FieldArguments& args, const CommandContext& context) {
  FieldBuildOptions build;
  build.voxelSize = args.band.voxelSize;
  build.resolution = args.band.resolutionOrDefault();
  build.halfWidth = args.band.halfWidth;
  build.field.domainPadding = args.padding;
  build.field.maxActiveVoxels = args.band.maxVoxels;
  build.field.maxMemoryBytes = context.options().budget.maxMemoryBytes;
  if (!args.smooth.empty()) {
    build.smooth =
        args.smooth == "pn" ? SmoothSurfaceSource::PnTriangles : SmoothSurfaceSource::LoopLimit;
  }
  build.progress = context.progress();
  return build;
}

nlohmann::json smoothJson(const SmoothFieldSurface& smooth) {
  nlohmann::json json = {{"source", smoothSurfaceSourceName(smooth.source)},
                         {"surface_seconds", smooth.surfaceSeconds},
                         {"field_seconds", smooth.fieldSeconds}};
  if (smooth.source == SmoothSurfaceSource::LoopLimit) {
    json["subdivided_faces"] = smooth.subdividedFaces;
  }
  return json;
}

Report runField(const FieldArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  const FieldBuildOptions build = fieldBuildOptions(args, context);
  LoadedInput input = loadFieldInput(args, build);
  reportRead(input, args.input, context);
  BuiltField built = buildApproximantField(std::move(input), build);
  const bool fromVdb =
      built.inputKind == InputKind::Field || built.inputKind == InputKind::LevelSet;
  if (fromVdb && (args.band.voxelSize > 0 || args.band.resolution > 0)) {
    built.warnings.insert(built.warnings.begin(),
                          "--voxel-size and --resolution are ignored for a .vdb input: the "
                          "field keeps the level set's voxels");
  }
  for (const std::string& message : built.warnings) warning(message);
  const ApproximantField& field = built.field;
  writeField(args.output, field,
             args.vdb.writeOptions(std::filesystem::path(args.input).filename().string(),
                                   field.halfWidth()));

  Report report;
  report.json = fieldJson(field);
  if (built.smooth) report.json["smooth"] = smoothJson(*built.smooth);
  const std::string wrote = addFileToFileKeys(
      report.json,
      {args.input, inputKindName(built.inputKind), args.output, clock.seconds(), built.warnings});
  report.text = wrote + "\n" + fieldText(report.json, "  ");
  if (built.signs && built.signs->method != SignMethod::none) {
    report.json["signs"] = signReportJson(*built.signs);
    report.text += "  " + signSummary(*built.signs);
  }
  return report;
}

std::vector<OutputFile> outputsOfField(const FieldArguments& args) {
  return {{"output", args.output, OutputFormat::Vdb}};
}

}  // namespace

void addFieldCommand(CommandRegistry& registry) {
  registry.add<FieldArguments>(
      {"field",
       "Build the squared-distance approximant field of a target and write it as one .vdb file:\n"
       "the distance grid plus companion grids (normal, curvatures, principal directions or\n"
       "tangent, flags) that any OpenVDB tool can open. Targets: meshes (.obj, .ply, .stl; made\n"
       "into a level set first, or with --smooth projected onto their smooth surface), level\n"
       "sets (.vdb), point sets (.xyz, .ply without faces), B-spline curves and polylines\n"
       "(.json, slice --polylines output included).\n"
       "Example: d2vdb field volumes/torus.vdb torus-field.vdb\n"
       "         d2vdb field volumes/helix.json helix-field.vdb --resolution 128 --half-width 4\n"
       "         d2vdb field volumes/bunny.obj bunny-field.vdb --smooth",
       "use a coarser --voxel-size or --resolution, or a smaller --half-width", declareField,
       runField, outputsOfField});
}

}  // namespace d2vdb::cli
