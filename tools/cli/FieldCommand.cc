// d2vdb field: the squared-distance approximant field of a mesh, a level set, a point set, a
// B-spline curve or a polyline, written as one .vdb file (FieldFile.h).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "Command.h"
#include "FieldReports.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/PolylineFile.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"

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
};

std::string lowerExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

// The "type" of a JSON file, or "" when it has none or is not valid JSON (the reader chosen
// afterwards then reports the problem with its position).
std::string jsonType(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const nlohmann::json json = nlohmann::json::parse(in, nullptr, false);
  if (json.is_object() && json.contains("type") && json["type"].is_string()) {
    return json["type"].get<std::string>();
  }
  return "";
}

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
};

BuiltField buildField(const Arguments& args, const ApproximantFieldOptions& fieldOptions,
                      const GlobalOptions& options) {
  const std::filesystem::path input(args.input);
  const std::string extension = lowerExtension(input);
  const ProgressCallback progress = makeProgressPrinter(options);
  BuiltField built;

  if (extension == ".vdb") {
    if (args.voxelSize > 0 || args.resolution > 0) {
      built.warnings.push_back(
          "--voxel-size and --resolution are ignored for a .vdb input: the "
          "field keeps the level set's voxels");
    }
    const std::vector<openvdb::GridBase::Ptr> grids = readAllGrids(input);
    if (isFieldFile(grids)) {
      // What readField() does, without reading the file a second time.
      built.inputKind = "field";
      built.field.emplace(fieldFromGrids(grids, input.string(), fieldOptions, progress));
    } else {
      built.inputKind = "level set";
      built.field.emplace(
          ApproximantField::fromLevelSet(readLevelSet(input), fieldOptions, progress));
    }
    return built;
  }

  if (extension == ".obj" || extension == ".stl" || extension == ".ply") {
    const TriangleMesh mesh = readMesh(input);
    if (!mesh.triangles.empty() || extension != ".ply") {
      status(options, "read " + args.input + ": " + std::to_string(mesh.vertexCount()) +
                          " vertices, " + std::to_string(mesh.triangleCount()) + " triangles");
      LevelSetOptions levelSet;
      levelSet.voxelSize = args.voxelSize;
      levelSet.resolution =
          args.voxelSize > 0 ? 0 : (args.resolution > 0 ? args.resolution : kDefaultResolution);
      levelSet.halfWidth = args.halfWidth;
      levelSet.maxActiveVoxels = args.maxVoxels;
      LevelSetResult result = meshToLevelSet(mesh, levelSet, progress);
      built.warnings = result.warnings;
      built.inputKind = "mesh";
      built.field.emplace(ApproximantField::fromLevelSet(result.grid, fieldOptions, progress));
      return built;
    }
    // A .ply without faces is a point set.
  }

  if (extension == ".xyz" || extension == ".ply") {
    const std::vector<Eigen::Vector3d> points = readPointSet(input);
    status(options, "read " + args.input + ": " + std::to_string(points.size()) + " points");
    Eigen::AlignedBox3d bounds;
    for (const Eigen::Vector3d& point : points) bounds.extend(point);
    const double voxelSize = chooseVoxelSize(args, bounds, "point set");
    built.inputKind = "points";
    built.field.emplace(
        ApproximantField::fromPoints(points, voxelSize, args.halfWidth, fieldOptions, progress));
    return built;
  }

  if (extension == ".json") {
    const std::string type = jsonType(input);
    if (type == "bspline_surface") {
      throw InputError("'" + args.input +
                       "' is a B-spline surface; fields are built for curves, point sets and "
                       "closed surfaces given as meshes or level sets (tessellate it first)");
    }
    std::optional<CurveTarget> curve;
    if (type == "bspline_curve") {
      curve.emplace(readCurveJson(input), args.padding);
      built.inputKind = "curve";
    } else {
      curve.emplace(readPolyline(input), args.padding);
      built.inputKind = "polyline";
    }
    curve->setLabel(input.filename().string());
    const double voxelSize = chooseVoxelSize(args, curve->curveBounds(), "curve");
    built.field.emplace(
        ApproximantField::fromCurve(*curve, voxelSize, args.halfWidth, fieldOptions, progress));
    return built;
  }

  throw InputError("cannot tell what '" + args.input + "' is from its extension '" + extension +
                   "'; 'd2vdb field' reads meshes (.obj, .ply, .stl), level sets (.vdb), point "
                   "sets (.xyz, .ply without faces), B-spline curves and polylines (.json)");
}

}  // namespace

void addFieldCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "field",
      "Build the squared-distance approximant field of a target and write it as one .vdb file:\n"
      "the distance grid plus companion grids (normal, curvatures, principal directions or\n"
      "tangent, flags) that any OpenVDB tool can open. Targets: meshes (.obj, .ply, .stl; made\n"
      "into a level set first), level sets (.vdb), point sets (.xyz, .ply without faces),\n"
      "B-spline curves and polylines (.json, slice --polylines output included).\n"
      "Example: d2vdb field volumes/torus.vdb torus-field.vdb\n"
      "         d2vdb field helix.json helix-field.vdb --resolution 128 --half-width 4");
  command->add_option("input", args->input, "Target file (mesh, .vdb, .xyz, curve .json)")
      ->required();
  command->add_option("output", args->output, "Output .vdb file (written atomically)")->required();
  auto* voxelSize = command->add_option("--voxel-size", args->voxelSize,
                                        "Voxel edge length of the band in world units");
  auto* resolution = command->add_option(
      "--resolution", args->resolution,
      "Voxels along the longest side of the target's bounding box (default 256; meshes, "
      "curves, points)");
  voxelSize->excludes(resolution)->check(CLI::PositiveNumber);
  resolution->excludes(voxelSize)->check(CLI::PositiveNumber);
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

}  // namespace d2vdb::cli
