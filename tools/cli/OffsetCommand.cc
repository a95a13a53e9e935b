// d2vdb offset: offset surfaces at given distances, either exactly through the support function
// (h + d, tessellated over a geodesic sphere of normals or a patch's Gauss image) or the OpenVDB
// way (level set of the input, LevelSetFilter::offset, marching cubes) as the reference. Each
// offset is written as a mesh, or as a level set when OUT ends in .vdb.
#include <openvdb/tools/LevelSetFilter.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "Command.h"
#include "SupportInputs.h"
#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/field/VoxelBudget.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/support/SupportTessellation.h"

namespace d2vdb::cli {
namespace {

constexpr int kDefaultResolution = 256;

struct Arguments {
  std::string input, output, method = "support";
  std::vector<double> distances;
  int degree = 16;
  double regularization = -1.0;
  int subdivisions = 6;
  bool allowSingular = false;
  bool patches = false;
  double parabolicRatio = -1.0;
  double voxelSize = 0.0;
  int resolution = 0;
  double halfWidth = 3.0;
  std::uint64_t maxVoxels = kDefaultMaxActiveVoxels;
};

std::string shortNumber(double value) {
  return formatNumber(value, 6);
}

// OUT itself for one distance; OUT's stem + "_d<distance>" + extension for several.
std::filesystem::path outputFor(const std::filesystem::path& output, double distance,
                                std::size_t count) {
  if (count == 1) return output;
  std::filesystem::path name = output;
  name.replace_filename(output.stem().string() + "_d" + shortNumber(distance) +
                        output.extension().string());
  return name;
}

bool isVdbPath(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".vdb";
}

// The level-set options of --voxel-size, --resolution (default 256), --half-width, --max-voxels.
LevelSetOptions levelSetOptionsOf(const Arguments& args) {
  LevelSetOptions options;
  options.voxelSize = args.voxelSize;
  options.resolution =
      args.voxelSize > 0 ? 0 : (args.resolution > 0 ? args.resolution : kDefaultResolution);
  options.halfWidth = args.halfWidth;
  options.maxActiveVoxels = args.maxVoxels;
  return options;
}

// One computed offset: a mesh, or a level set for a .vdb output.
struct Written {
  double distance = 0.0;
  std::string path;
  TriangleMesh mesh;
  openvdb::FloatGrid::Ptr grid;
  double seconds = 0.0;
};

// Writes every offset once all are computed, so a bad input never leaves some of them written.
void writeAll(const std::vector<Written>& written, const GlobalOptions& options) {
  for (const Written& w : written) {
    if (w.grid) {
      writeVdb(w.path, {w.grid});
      status(options, "wrote " + w.path + ": offset " + shortNumber(w.distance) +
                          ", level set of " + std::to_string(w.grid->activeVoxelCount()) +
                          " active voxels");
    } else {
      writeMesh(w.path, w.mesh);
      status(options, "wrote " + w.path + ": offset " + shortNumber(w.distance) + ", " +
                          std::to_string(w.mesh.vertexCount()) + " vertices");
    }
  }
}

nlohmann::json writtenJson(const std::vector<Written>& written) {
  nlohmann::json outputs = nlohmann::json::array();
  for (const Written& w : written) {
    nlohmann::json entry = {{"distance", w.distance}, {"output", w.path}, {"seconds", w.seconds}};
    if (w.grid) {
      entry["voxel_size"] = w.grid->voxelSize()[0];
      entry["active_voxels"] = w.grid->activeVoxelCount();
    } else {
      entry["vertices"] = w.mesh.vertexCount();
      entry["triangles"] = w.mesh.triangleCount();
    }
    outputs.push_back(entry);
  }
  return outputs;
}

// The support-function method: fit (or read) h, check every distance, then tessellate x_{h+d}.
nlohmann::json offsetBySupport(const Arguments& args, const GlobalOptions& options,
                               std::vector<Written>& written, std::vector<std::string>& warnings) {
  const SupportInput input = loadSupportInput(args.input, options);
  warnings.insert(warnings.end(), input.warnings.begin(), input.warnings.end());
  if (!input.document) {
    status(options, "fitting degree " + std::to_string(args.degree) + " to " +
                        std::to_string(input.samples.points.size()) + " samples of " + args.input +
                        " (" + input.kind + ")");
  }
  const CheckedSupport support =
      fitAndCheck(input, args.input, args.degree, args.regularization, args.allowSingular);
  warnings.insert(warnings.end(), support.warnings.begin(), support.warnings.end());
  for (const double d : args.distances) {
    if (!support.validity.regular()) break;  // already refused or warned about
    try {
      requireRegularOffset(support.validity, d);
    } catch (const InputError& error) {
      if (!args.allowSingular) {
        throw InputError(std::string(error.what()) +
                         "; choose a distance inside the safe range or pass --allow-singular");
      }
      warnings.push_back(std::string(error.what()) + " (kept: --allow-singular)");
    }
  }
  const SphericalTriangulation domain =
      support.document.patch ? *support.document.patch : geodesicSphere(args.subdivisions);
  const bool toLevelSet = isVdbPath(args.output);
  if (toLevelSet && support.document.patch) {
    throw InputError("'" + args.input +
                     "' is fitted over a patch's Gauss image: its offsets are open surfaces, which "
                     "have no inside for a signed level set; write a mesh (.obj, .ply, .stl)");
  }
  for (const double d : args.distances) {
    const Stopwatch clock;
    Written w;
    w.distance = d;
    w.path = outputFor(args.output, d, args.distances.size()).string();
    w.mesh = tessellateSupport(support.document.function, domain, d);
    if (toLevelSet) {
      LevelSetResult result =
          meshToLevelSet(w.mesh, levelSetOptionsOf(args), makeProgressPrinter(options));
      warnings.insert(warnings.end(), result.warnings.begin(), result.warnings.end());
      w.grid = result.grid;
      w.mesh = TriangleMesh();
    }
    w.seconds = clock.seconds();
    written.push_back(std::move(w));
  }
  writeAll(written, options);
  nlohmann::json report = supportJson(support);
  report["input_kind"] = input.kind;
  report["tessellation"] =
      support.document.patch
          ? std::string("gauss image")
          : "geodesic sphere, " + std::to_string(args.subdivisions) + " subdivisions";
  return report;
}

// The support-function method over the patches of a non-convex surface: each patch's offset over
// its Gauss image, all in one mesh (open pieces; gaps where no patch covers the surface).
nlohmann::json offsetByPatches(const Arguments& args, const GlobalOptions& options,
                               std::vector<Written>& written, std::vector<std::string>& warnings) {
  if (isVdbPath(args.output)) {
    throw InputError(
        "--patches gives open pieces of the offset surface, which have no inside for "
        "a signed level set; write a mesh (.obj, .ply, .stl)");
  }
  const PatchedSupport patched =
      fitPatches(args.input, options, args.degree, args.regularization, args.parabolicRatio);
  warnings.insert(warnings.end(), patched.warnings.begin(), patched.warnings.end());
  for (const double d : args.distances) {
    requireRegularPatchOffset(patched, d, args.allowSingular, warnings);
  }
  for (const double d : args.distances) {
    const Stopwatch clock;
    Written w;
    w.distance = d;
    w.path = outputFor(args.output, d, args.distances.size()).string();
    for (const SupportPatch& p : patched.set.patches) {
      const TriangleMesh piece = tessellateSupport(p.function, p.gaussImage.gaussImage, d);
      const auto base = static_cast<TriangleMesh::Index>(w.mesh.positions.size());
      w.mesh.positions.insert(w.mesh.positions.end(), piece.positions.begin(),
                              piece.positions.end());
      w.mesh.normals.insert(w.mesh.normals.end(), piece.normals.begin(), piece.normals.end());
      for (const auto& t : piece.triangles) {
        w.mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
      }
    }
    w.seconds = clock.seconds();
    written.push_back(std::move(w));
  }
  writeAll(written, options);
  nlohmann::json report = patchesJson(patched);
  report["tessellation"] = "gauss images of the patches";
  return report;
}

// The level-set method (OpenVDB's way): level set of the input, offset by LevelSetFilter in steps
// of at most half a voxel with renormalisation, marching cubes.
nlohmann::json offsetByLevelSet(const Arguments& args, const GlobalOptions& options,
                                std::vector<Written>& written, std::vector<std::string>& warnings) {
  const ProgressCallback progress = makeProgressPrinter(options);
  const Stopwatch setup;
  LoadOptions load;
  load.purpose = "the input of 'd2vdb offset --method levelset' (a closed mesh or a level set)";
  LoadedInput loaded = loadInput(args.input, {InputKind::Mesh, InputKind::LevelSet}, load);
  openvdb::FloatGrid::Ptr levelSet;
  std::string kind;
  if (loaded.kind() == InputKind::LevelSet) {
    levelSet = std::move(loaded).take<LevelSetInput>().floatGrid();
    kind = "level set";
  } else {
    const TriangleMesh mesh = std::move(loaded).take<MeshInput>().mesh;
    if (mesh.triangles.empty()) {
      throw InputError("'" + args.input +
                       "' has no triangles: the level-set method needs a closed mesh or a level "
                       "set");
    }
    LevelSetResult result = meshToLevelSet(mesh, levelSetOptionsOf(args), progress);
    warnings.insert(warnings.end(), result.warnings.begin(), result.warnings.end());
    levelSet = result.grid;
    kind = "mesh";
  }
  const double voxel = levelSet->voxelSize()[0];
  const double setupSeconds = setup.seconds();
  // The band keeps its width while it moves, so an outward offset grows it with the surface:
  // bound the offset surface's area by that of the bounding box grown by d.
  const openvdb::CoordBBox indexBox = levelSet->evalActiveVoxelBoundingBox();
  const openvdb::Vec3d size = indexBox.dim().asVec3d() * voxel;
  for (const double d : args.distances) {
    const double grow = std::max(0.0, 2.0 * d);
    const double sx = size.x() + grow, sy = size.y() + grow, sz = size.z() + grow;
    const double area = 2.0 * (sx * sy + sy * sz + sz * sx);
    const double estimate = area / (voxel * voxel) * 2.0 * args.halfWidth * 1.25;
    if (estimate > static_cast<double>(args.maxVoxels)) {
      throw InputError("offsetting by " + shortNumber(d) + " at voxel size " + shortNumber(voxel) +
                       " would need about " + std::to_string(static_cast<long long>(estimate)) +
                       " active voxels, above --max-voxels " + std::to_string(args.maxVoxels) +
                       "; use a larger --voxel-size");
    }
  }
  for (const double d : args.distances) {
    const Stopwatch clock;
    Written w;
    w.distance = d;
    w.path = outputFor(args.output, d, args.distances.size()).string();
    w.grid = levelSet->deepCopy();
    openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*w.grid);
    filter.offset(static_cast<float>(-d));  // OpenVDB adds its argument to the distances
    IsoSurfaceOptions iso;
    w.mesh = extractIsoSurface(*w.grid, iso, progress);
    if (w.mesh.triangles.empty()) {
      throw InputError("the offset at distance " + shortNumber(d) + " of '" + args.input +
                       "' is empty (the body is thinner than 2 |d|)");
    }
    if (isVdbPath(args.output)) {
      w.mesh = TriangleMesh();  // the offset level set itself is the output
    } else {
      w.grid.reset();
    }
    w.seconds = clock.seconds();
    written.push_back(std::move(w));
  }
  writeAll(written, options);
  return {{"input_kind", kind},
          {"voxel_size", voxel},
          {"half_width", args.halfWidth},
          {"active_voxels", levelSet->activeVoxelCount()},
          {"setup_seconds", setupSeconds}};
}

}  // namespace

void addOffsetCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "offset",
      "Offset a surface by signed distances d (along the outward normals; d < 0 moves inward)\n"
      "and write each offset as a mesh. --method support (default): the support function h is\n"
      "fitted (or read from a .json written by 'd2vdb support') and the offset is exactly\n"
      "h + d, tessellated over a geodesic sphere of normals (closed inputs) or the input's\n"
      "Gauss image (open meshes); a distance outside the safe range (where a principal radius\n"
      "r + d would change sign: cusps, swallowtails) is refused unless --allow-singular, and so\n"
      "is a non-convex closed input unless --patches: then the surface (a mesh or level set) is\n"
      "split into patches of one curvature sign, each offset over its Gauss image, all written\n"
      "as one mesh of open pieces. --method levelset: the OpenVDB way, as a reference: level\n"
      "set of the input, LevelSetFilter::offset, marching cubes. Several --distance values give\n"
      "OUT's name with _d<distance> inserted before the extension. An OUT ending in .vdb gets\n"
      "each offset as a level set (--method levelset: the offset grid itself; support: the\n"
      "tessellation converted at --voxel-size or --resolution, so choose --subdivisions fine\n"
      "enough for that voxel size).\n"
      "Example: d2vdb offset ellipsoid.obj out.obj --distance -0.3 --distance 0.25 --degree 24\n"
      "         d2vdb offset volumes/torus.vdb torus-out.obj --distance 0.1 --patches\n"
      "         d2vdb offset volumes/bunny.vdb bunny-out.obj --distance 0.01 --method levelset");
  command
      ->add_option("input", args->input, "Mesh, point set (.ply), .vdb or support-function .json")
      ->required();
  command
      ->add_option("output", args->output,
                   "Output mesh (.obj, .ply, .stl) or level set (.vdb); written atomically")
      ->required();
  command->add_option("--distance", args->distances, "Signed offset distance (repeatable)")
      ->required()
      ->allow_extra_args(false);
  command->add_option("--method", args->method, "support or levelset")
      ->capture_default_str()
      ->check(CLI::IsMember({"support", "levelset"}));
  command
      ->add_option("--degree", args->degree,
                   "support: spherical-harmonic degree of the fit (inputs other than .json)")
      ->capture_default_str();
  command
      ->add_option("--regularization", args->regularization,
                   "support: smoothness weight of the fit (default 1e-10 sphere, 1e-13 patch)")
      ->check(CLI::Range(0.0, 1e6));
  command
      ->add_option("--subdivisions", args->subdivisions,
                   "support: geodesic sphere of normals, 10 * 4^s + 2 vertices")
      ->capture_default_str()
      ->check(CLI::Range(0, 9));
  command->add_flag("--allow-singular", args->allowSingular,
                    "support: write offsets outside the safe range or of a singular function");
  command->add_flag("--patches", args->patches,
                    "support: split a non-convex mesh or level set into patches of one curvature "
                    "sign and offset each over its Gauss image");
  auto* voxelSize =
      command->add_option("--voxel-size", args->voxelSize,
                          "levelset and .vdb outputs: voxel edge length in world units");
  auto* resolution = command->add_option(
      "--resolution", args->resolution,
      "levelset and .vdb outputs: voxels along the longest side of the mesh's bounding box "
      "(default 256)");
  voxelSize->excludes(resolution)->check(positiveNumber());
  resolution->excludes(voxelSize)->check(positiveNumber());
  command
      ->add_option("--half-width", args->halfWidth,
                   "levelset and .vdb outputs: band half-width in voxels")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  command
      ->add_option("--max-voxels", args->maxVoxels,
                   "levelset and .vdb outputs: refuse when the estimated number of active voxels "
                   "exceeds this")
      ->capture_default_str();
  addParabolicRatioOption(command, args->parabolicRatio);
  command->add_flag("--json", options.json, "Print the report as JSON on stdout");

  registry.add(command, [args, &options]() {
    const Stopwatch clock;
    // An unsupported extension fails before any work.
    if (!isVdbPath(args->output)) {
      try {
        meshFormatFromPath(args->output);
      } catch (const InputError&) {
        throw InputError("the output '" + args->output +
                         "' must be a mesh (.obj, .ply, .stl) or a level set (.vdb)");
      }
    }
    for (const double d : args->distances) {
      if (!std::isfinite(d)) throw InputError("--distance must be a finite number");
    }
    std::vector<Written> written;
    std::vector<std::string> warnings;
    if (args->patches && args->method != "support") {
      throw InputError("--patches belongs to --method support");
    }
    nlohmann::json report = args->method != "support"
                                ? offsetByLevelSet(*args, options, written, warnings)
                            : args->patches ? offsetByPatches(*args, options, written, warnings)
                                            : offsetBySupport(*args, options, written, warnings);
    for (const std::string& message : warnings) warning(message);
    report["input"] = args->input;
    report["method"] = args->method;
    report["distances"] = args->distances;
    report["outputs"] = writtenJson(written);
    report["warnings"] = warnings;
    report["seconds"] = clock.seconds();
    if (options.json) {
      printJson(report);
    } else if (args->patches) {
      std::string summary = patchesText(report, "  ");
      summary.pop_back();
      status(options, "offset " + args->input + " by support-function patches (" +
                          std::to_string(clock.seconds()) + " s):\n" + summary);
    } else if (args->method == "support") {
      std::string summary = supportText(report, "  ");
      summary.pop_back();
      status(options, "offset " + args->input + " by support function (" +
                          std::to_string(clock.seconds()) + " s):\n" + summary);
    } else {
      status(options, "offset " + args->input + " by level set, voxel size " +
                          shortNumber(report["voxel_size"].get<double>()) + " (" +
                          std::to_string(clock.seconds()) + " s)");
    }
    return kSuccess;
  });
}

// TRANSITION: the old registration until this command has its CommandDefinition.
void addOffsetCommand(CommandRegistry& registry) {
  addOffsetCommand(registry.app(), registry, registry.legacyOptions());
}

}  // namespace d2vdb::cli
