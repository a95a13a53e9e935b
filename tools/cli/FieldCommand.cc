// d2vdb field: the squared-distance approximant field of a mesh, a level set, a point set, a
// B-spline curve or a polyline, written as one .vdb file (FieldFile.h).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "Command.h"
#include "FieldReports.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/field/SmoothSurfaceField.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/PolylineFile.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/PnTriangles.h"

namespace d2vdb::cli {
namespace {

constexpr int kDefaultResolution = 256;

struct Arguments {
  std::string input, output;
  double voxelSize = 0;
  int resolution = 0;
  double halfWidth = 3;
  double padding = 0.5;
  std::uint64_t maxVoxels = kDefaultMaxActiveVoxels;
  bool half = false, noCompression = false;
  std::string smooth;  ///< "", "loop" or "pn": build a mesh's field from its smooth surface
};

// Voxel size for targets whose size the command measures itself (curves, points).
double chooseVoxelSize(const Arguments& args, const Eigen::AlignedBox3d& bounds,
                       const std::string& what) {
  if (args.voxelSize > 0) return args.voxelSize;
  const int resolution = args.resolution > 0 ? args.resolution : kDefaultResolution;
  const double longest = bounds.sizes().maxCoeff();
  if (!(longest > 0)) {
    throw InputError("the " + what + " has a bounding box of zero extent, so --resolution " +
                     "cannot set the voxel size; give --voxel-size");
  }
  return longest / resolution;
}

struct BuiltField {
  std::optional<ApproximantField> field;
  std::string inputKind;  // "mesh", "level set", "field", "points", "curve", "polyline"
  std::vector<std::string> warnings;
  nlohmann::json smooth;  // with --smooth: what the smooth surface was built from
};

/// The field of a mesh's smooth surface (--smooth): half-edge mesh, source, pseudo-manifold,
/// then every band voxel projected onto it.
void buildSmoothField(const Arguments& args, const TriangleMesh& mesh,
                      const ApproximantFieldOptions& fieldOptions, const ProgressCallback& progress,
                      BuiltField& built) {
  const Stopwatch clock;
  std::shared_ptr<const HalfEdgeMesh> halfEdges;
  try {
    halfEdges = std::make_shared<const HalfEdgeMesh>(mesh);
  } catch (const InputError& error) {
    throw InputError(args.input + ": " + error.what());
  }
  Eigen::AlignedBox3d bounds;
  for (const Eigen::Vector3f& p : mesh.positions) bounds.extend(p.cast<double>());
  const double voxelSize = chooseVoxelSize(args, bounds, "mesh");
  std::unique_ptr<SourceSurface> source;
  std::size_t subdivided = 0;
  if (args.smooth == "pn") {
    source = std::make_unique<PnTriangles>(halfEdges);
  } else {
    auto loop = std::make_unique<LoopLimitSurface>(halfEdges);
    subdivided = loop->subdividedFaceCount();
    source = std::move(loop);
  }
  const PseudoManifold surface(*source, PseudoManifoldOptions{}, progress);
  const double surfaceSeconds = clock.seconds();
  built.field.emplace(smoothSurfaceField(surface, voxelSize, args.halfWidth,
                                         std::filesystem::path(args.input).filename().string(),
                                         fieldOptions, progress));
  built.inputKind = "mesh";
  built.smooth = {{"source", args.smooth},
                  {"surface_seconds", surfaceSeconds},
                  {"field_seconds", clock.seconds() - surfaceSeconds}};
  if (args.smooth == "loop") built.smooth["subdivided_faces"] = subdivided;
}

BuiltField buildField(const Arguments& args, const ApproximantFieldOptions& fieldOptions,
                      const GlobalOptions& options) {
  LoadOptions load;
  load.purpose = "the input of 'd2vdb field'";
  load.field = fieldOptions;
  load.progress = makeProgressPrinter(options);
  if (!args.smooth.empty()) {
    // --smooth: meshes only, refused before anything else is built.
    load.purpose = "the input of 'd2vdb field --smooth' (the field of a mesh's smooth surface)";
    TriangleMesh mesh = loadInput(args.input, {InputKind::Mesh}, load).take<MeshInput>().mesh;
    status(options, "read " + args.input + ": " + std::to_string(mesh.vertexCount()) +
                        " vertices, " + std::to_string(mesh.triangleCount()) + " triangles");
    BuiltField built;
    buildSmoothField(args, mesh, fieldOptions, load.progress, built);
    return built;
  }
  LoadedInput input = loadInput(args.input,
                                {InputKind::Mesh, InputKind::PointSet, InputKind::Field,
                                 InputKind::Curve, InputKind::Polylines, InputKind::Surface},
                                load);
  BuiltField built;
  switch (input.kind()) {
    case InputKind::Field: {
      if (args.voxelSize > 0 || args.resolution > 0) {
        built.warnings.push_back(
            "--voxel-size and --resolution are ignored for a .vdb input: the "
            "field keeps the level set's voxels");
      }
      FieldInput field = std::move(input).take<FieldInput>();
      built.inputKind = field.stored ? "field" : "level set";
      built.field.emplace(std::move(field.field));
      return built;
    }
    case InputKind::Mesh: {
      const TriangleMesh mesh = std::move(input).take<MeshInput>().mesh;
      status(options, "read " + args.input + ": " + std::to_string(mesh.vertexCount()) +
                          " vertices, " + std::to_string(mesh.triangleCount()) + " triangles");
      LevelSetOptions levelSet;
      levelSet.voxelSize = args.voxelSize;
      levelSet.resolution =
          args.voxelSize > 0 ? 0 : (args.resolution > 0 ? args.resolution : kDefaultResolution);
      levelSet.halfWidth = args.halfWidth;
      levelSet.maxActiveVoxels = args.maxVoxels;
      LevelSetResult result = meshToLevelSet(mesh, levelSet, load.progress);
      built.warnings = result.warnings;
      built.inputKind = "mesh";
      built.field.emplace(ApproximantField::fromLevelSet(result.grid, fieldOptions, load.progress));
      return built;
    }
    case InputKind::PointSet: {
      const std::vector<Eigen::Vector3d> points = std::move(input).take<PointSetInput>().points;
      status(options, "read " + args.input + ": " + std::to_string(points.size()) + " points");
      Eigen::AlignedBox3d bounds;
      for (const Eigen::Vector3d& point : points) bounds.extend(point);
      const double voxelSize = chooseVoxelSize(args, bounds, "point set");
      built.inputKind = "points";
      built.field.emplace(ApproximantField::fromPoints(points, voxelSize, args.halfWidth,
                                                       fieldOptions, load.progress));
      return built;
    }
    case InputKind::Curve:
    case InputKind::Polylines: {
      const std::filesystem::path path = input.path;
      std::optional<CurveTarget> curve;
      if (input.kind() == InputKind::Curve) {
        curve.emplace(std::move(input).take<BSplineCurve>(), args.padding);
        built.inputKind = "curve";
      } else {
        curve.emplace(onlyPolyline(std::move(input).take<PolylinesInput>().polylines, path),
                      args.padding);
        built.inputKind = "polyline";
      }
      curve->setLabel(path.filename().string());
      const double voxelSize = chooseVoxelSize(args, curve->curveBounds(), "curve");
      built.field.emplace(ApproximantField::fromCurve(*curve, voxelSize, args.halfWidth,
                                                      fieldOptions, load.progress));
      return built;
    }
    case InputKind::Surface:
      throw InputError("'" + args.input +
                       "' is a B-spline surface; fields are built for curves, point sets and "
                       "closed surfaces given as meshes or level sets (tessellate it first)");
    default:
      break;
  }
  throw RuntimeFailure("d2vdb field: input kind without a field");
}

}  // namespace

void addFieldCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "field",
      "Build the squared-distance approximant field of a target and write it as one .vdb file:\n"
      "the distance grid plus companion grids (normal, curvatures, principal directions or\n"
      "tangent, flags) that any OpenVDB tool can open. Targets: meshes (.obj, .ply, .stl; made\n"
      "into a level set first, or with --smooth projected onto their smooth surface), level\n"
      "sets (.vdb), point sets (.xyz, .ply without faces), B-spline curves and polylines\n"
      "(.json, slice --polylines output included).\n"
      "Example: d2vdb field volumes/torus.vdb torus-field.vdb\n"
      "         d2vdb field helix.json helix-field.vdb --resolution 128 --half-width 4\n"
      "         d2vdb field volumes/bunny.obj bunny-field.vdb --smooth");
  command->add_option("input", args->input, "Target file (mesh, .vdb, .xyz, curve .json)")
      ->required();
  command->add_option("output", args->output, "Output .vdb file (written atomically)")->required();
  auto* voxelSize = command->add_option("--voxel-size", args->voxelSize,
                                        "Voxel edge length of the band in world units");
  auto* resolution = command->add_option(
      "--resolution", args->resolution,
      "Voxels along the longest side of the target's bounding box (default 256; meshes, "
      "curves, points)");
  voxelSize->excludes(resolution)->check(positiveNumber());
  resolution->excludes(voxelSize)->check(positiveNumber());
  command->add_option("--half-width", args->halfWidth, "Narrow-band half-width in voxels")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  command
      ->add_option("--padding", args->padding,
                   "Working domain: the target's bounding box padded on every side by this "
                   "fraction of its largest side")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  command
      ->add_option("--max-voxels", args->maxVoxels,
                   "Refuse when the estimated number of active voxels exceeds this")
      ->capture_default_str();
  command->add_flag("--half", args->half, "Store values as 16-bit half floats (smaller, lossy)");
  command->add_flag("--no-compression", args->noCompression, "Write without Blosc compression");
  command
      ->add_option("--smooth", args->smooth,
                   "Meshes: the field of the mesh's smooth (C-infinity) surface, every band "
                   "voxel projected onto it (source: loop, the default, or pn)")
      ->expected(0, 1)
      ->default_str("loop")
      ->check(CLI::IsMember({"loop", "pn"}));
  command->add_flag("--json", options.json, "Print the summary as JSON on stdout");

  registry.add(command, [args, &options]() {
    const Stopwatch clock;
    ApproximantFieldOptions fieldOptions;
    fieldOptions.domainPadding = args->padding;
    fieldOptions.maxActiveVoxels = args->maxVoxels;
    BuiltField built = buildField(*args, fieldOptions, options);
    for (const std::string& message : built.warnings) warning(message);
    const ApproximantField& field = *built.field;

    VdbWriteOptions writeOptions;
    writeOptions.blosc = !args->noCompression;
    writeOptions.halfFloat = args->half;
    writeOptions.source = std::filesystem::path(args->input).filename().string();
    writeOptions.halfWidth = field.halfWidth();
    writeField(args->output, field, writeOptions);

    nlohmann::json report = fieldJson(field);
    report["input"] = args->input;
    report["input_kind"] = built.inputKind;
    report["output"] = args->output;
    report["seconds"] = clock.seconds();
    report["warnings"] = built.warnings;
    if (!built.smooth.is_null()) report["smooth"] = built.smooth;
    if (options.json) {
      printJson(report);
    } else {
      std::string summary = fieldText(report, "  ");
      summary.pop_back();  // status() ends the line
      status(options, "wrote " + args->output + " (" + built.inputKind + " " + args->input + ", " +
                          std::to_string(clock.seconds()) + " s):\n" + summary);
    }
    return kSuccess;
  });
}

// TRANSITION: the old registration until this command has its CommandDefinition.
void addFieldCommand(CommandRegistry& registry) {
  addFieldCommand(registry.app(), registry, registry.legacyOptions());
}

}  // namespace d2vdb::cli
