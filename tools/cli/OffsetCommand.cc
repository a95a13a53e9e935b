// d2vdb offset: offset surfaces at given distances, either exactly through the support function
// (h + d, tessellated over a geodesic sphere of normals or a patch's Gauss image) or the OpenVDB
// way (level set of the input, LevelSetFilter::offset, marching cubes) as the reference. Each
// offset is written as a mesh, or as a level set when OUT ends in .vdb.
#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "Command.h"
#include "SharedOptions.h"
#include "SupportReports.h"
#include "d2vdb/core/AtomicFileSet.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/io/LevelSetOffsets.h"
#include "d2vdb/io/SupportInput.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/support/SupportOffsets.h"
#include "d2vdb/support/SupportTessellation.h"

namespace d2vdb::cli {
namespace {

struct OffsetArguments {
  std::string input, output, method = "support";
  std::vector<double> distances;
  int degree = 16;
  double regularization = -1.0;
  int subdivisions = 6;
  bool allowSingular = false;
  bool patches = false;
  double parabolicRatio = -1.0;
  BandArguments band;
};

void declareOffset(CLI::App& command, OffsetArguments& args) {
  command.add_option("input", args.input, "Mesh, point set (.ply), .vdb or support-function .json")
      ->required();
  command
      .add_option("output", args.output,
                  "Output mesh (.obj, .ply, .stl) or level set (.vdb); written atomically")
      ->required();
  command.add_option("--distance", args.distances, "Signed offset distance (repeatable)")
      ->required()
      ->allow_extra_args(false);
  command.add_option("--method", args.method, "support or levelset")
      ->capture_default_str()
      ->check(CLI::IsMember({"support", "levelset"}));
  command
      .add_option("--degree", args.degree,
                  "support: spherical-harmonic degree of the fit (inputs other than .json)")
      ->capture_default_str();
  command
      .add_option("--regularization", args.regularization,
                  "support: smoothness weight of the fit (default 1e-10 sphere, 1e-13 patch)")
      ->check(CLI::Range(0.0, 1e6));
  command
      .add_option("--subdivisions", args.subdivisions,
                  "support: geodesic sphere of normals, 10 * 4^s + 2 vertices")
      ->capture_default_str()
      ->check(CLI::Range(0, 9));
  command.add_flag("--allow-singular", args.allowSingular,
                   "support: write offsets outside the safe range or of a singular function");
  command.add_flag("--patches", args.patches,
                   "support: split a non-convex mesh or level set into patches of one curvature "
                   "sign and offset each over its Gauss image");
  declareBandOptions(command, args.band, {"the mesh", "levelset and .vdb outputs: "});
  addParabolicRatioOption(command, args.parabolicRatio);
}

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

// One computed offset: a mesh, or a level set for a .vdb output.
struct Written {
  double distance = 0.0;
  std::string path;
  TriangleMesh mesh;
  openvdb::FloatGrid::Ptr grid;
  double seconds = 0.0;
};

// What one method produced: its own report keys, the offsets (written) and the warnings.
struct OffsetRun {
  nlohmann::json json;
  std::vector<Written> written;
  std::vector<std::string> warnings;
};

// Writes every offset once all are computed, each to a temporary name, and replaces the targets
// only when all were written: a bad input or a failed write never leaves some of them written.
void writeAll(const std::vector<Written>& written, const CommandContext& context) {
  AtomicFileSet files;
  for (const Written& w : written) {
    files.stage(w.path, [&w](const std::filesystem::path& temporary) {
      if (w.grid) {
        writeVdb(temporary, {w.grid});
      } else {
        writeMesh(temporary, w.mesh);
      }
    });
  }
  files.commit();
  for (const Written& w : written) {
    if (w.grid) {
      context.status("wrote " + w.path + ": offset " + shortNumber(w.distance) + ", level set of " +
                     std::to_string(w.grid->activeVoxelCount()) + " active voxels");
    } else {
      context.status("wrote " + w.path + ": offset " + shortNumber(w.distance) + ", " +
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
OffsetRun offsetBySupport(const OffsetArguments& args, const CommandContext& context) {
  OffsetRun run;
  const SupportInput input = loadSupportInput(args.input, context.progress());
  run.warnings = input.warnings;
  if (!input.document) {
    context.status("fitting degree " + std::to_string(args.degree) + " to " +
                   std::to_string(input.samples.points.size()) + " samples of " + args.input +
                   " (" + supportInputKindName(input.kind) + ")");
  }
  const CheckedSupport support =
      fitAndCheck(input, args.input, {args.degree, args.regularization, args.allowSingular});
  run.warnings.insert(run.warnings.end(), support.warnings.begin(), support.warnings.end());
  requireRegularOffsets(support.validity, args.distances, args.allowSingular, run.warnings);
  const bool toLevelSet = isVdbPath(args.output);
  if (toLevelSet && support.document.patch) {
    throw InputError("'" + args.input +
                     "' is fitted over a patch's Gauss image: its offsets are open surfaces, which "
                     "have no inside for a signed level set; write a mesh (.obj, .ply, .stl)");
  }
  // Every offset's tessellation (and, for .vdb outputs, its conversion) within the budget before
  // the domain is built; each level set's voxels are checked by meshToLevelSet().
  enforceSupportOffsetBudget(
      support.document.patch, args.subdivisions, args.distances.size(),
      toLevelSet ? std::nullopt : std::optional<MeshFormat>(meshFormatFromPath(args.output)),
      toLevelSet ? kLevelSetBytesPerTriangle : 0.0, context.options().budget);
  const SphericalTriangulation domain =
      tessellationDomain(support.document.patch, args.subdivisions);
  for (const double d : args.distances) {
    const Stopwatch clock;
    Written w;
    w.distance = d;
    w.path = outputFor(args.output, d, args.distances.size()).string();
    w.mesh = tessellateSupport(support.document.function, domain, d);
    if (toLevelSet) {
      LevelSetResult result = meshToLevelSet(
          w.mesh, args.band.levelSetOptions(context.options().budget), context.progress());
      run.warnings.insert(run.warnings.end(), result.warnings.begin(), result.warnings.end());
      w.grid = result.grid;
      w.mesh = TriangleMesh();
    }
    w.seconds = clock.seconds();
    run.written.push_back(std::move(w));
  }
  writeAll(run.written, context);
  run.json = supportJson(support);
  run.json["input_kind"] = supportInputKindName(input.kind);
  run.json["tessellation"] =
      support.document.patch
          ? std::string("gauss image")
          : "geodesic sphere, " + std::to_string(args.subdivisions) + " subdivisions";
  return run;
}

// The support-function method over the patches of a non-convex surface: each patch's offset over
// its Gauss image, all in one mesh (open pieces; gaps where no patch covers the surface).
OffsetRun offsetByPatches(const OffsetArguments& args, const CommandContext& context) {
  if (isVdbPath(args.output)) {
    throw InputError(
        "--patches gives open pieces of the offset surface, which have no inside for "
        "a signed level set; write a mesh (.obj, .ply, .stl)");
  }
  OffsetRun run;
  const PatchedSupport patched =
      loadAndFitPatches(args.input, args.degree, args.regularization, args.parabolicRatio, context);
  run.warnings = patched.warnings;
  requireRegularPatchOffsets(patched.set, args.distances, args.allowSingular, run.warnings);
  for (const double d : args.distances) {
    const Stopwatch clock;
    Written w;
    w.distance = d;
    w.path = outputFor(args.output, d, args.distances.size()).string();
    w.mesh = tessellatePatchOffsets(patched.set, d);
    w.seconds = clock.seconds();
    run.written.push_back(std::move(w));
  }
  writeAll(run.written, context);
  run.json = patchesJson(patched);
  run.json["tessellation"] = "gauss images of the patches";
  return run;
}

// The level-set method (OpenVDB's way): level set of the input, offset by LevelSetFilter in steps
// of at most half a voxel with renormalisation, marching cubes.
OffsetRun offsetByLevelSet(const OffsetArguments& args, const CommandContext& context) {
  const ProgressCallback progress = context.progress();
  const Stopwatch setup;
  OffsetRun run;
  const OffsetLevelSet input =
      loadOffsetLevelSet(args.input, args.band.levelSetOptions(context.options().budget), progress);
  run.warnings = input.warnings;
  const double voxel = input.grid->voxelSize()[0];
  const double setupSeconds = setup.seconds();
  checkLevelSetOffsetBudget(*input.grid, args.distances, args.band.halfWidth, args.band.maxVoxels);
  for (const double d : args.distances) {
    const Stopwatch clock;
    Written w;
    w.distance = d;
    w.path = outputFor(args.output, d, args.distances.size()).string();
    LevelSetOffset offset = offsetLevelSet(*input.grid, d, args.input, progress);
    if (isVdbPath(args.output)) {
      w.grid = std::move(offset.grid);  // the offset level set itself is the output
    } else {
      w.mesh = std::move(offset.mesh);
    }
    w.seconds = clock.seconds();
    run.written.push_back(std::move(w));
  }
  writeAll(run.written, context);
  run.json = {{"input_kind", inputKindName(input.kind)},
              {"voxel_size", voxel},
              {"half_width", args.band.halfWidth},
              {"active_voxels", input.grid->activeVoxelCount()},
              {"setup_seconds", setupSeconds}};
  return run;
}

Report runOffset(const OffsetArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  for (const double d : args.distances) {
    if (!std::isfinite(d)) throw InputError("--distance must be a finite number");
  }
  if (args.patches && args.method != "support") {
    throw InputError("--patches belongs to --method support");
  }
  const OffsetRun run = args.method != "support" ? offsetByLevelSet(args, context)
                        : args.patches           ? offsetByPatches(args, context)
                                                 : offsetBySupport(args, context);
  for (const std::string& message : run.warnings) warning(message);
  Report report;
  report.json = run.json;
  report.json["input"] = args.input;
  report.json["method"] = args.method;
  report.json["distances"] = args.distances;
  report.json["outputs"] = writtenJson(run.written);
  report.json["warnings"] = run.warnings;
  report.json["seconds"] = clock.seconds();
  const std::string seconds = std::to_string(clock.seconds()) + " s";
  if (args.patches) {
    report.text = "offset " + args.input + " by support-function patches (" + seconds + "):\n" +
                  patchesText(report.json, "  ");
  } else if (args.method == "support") {
    report.text = "offset " + args.input + " by support function (" + seconds + "):\n" +
                  supportText(report.json, "  ");
  } else {
    report.text = "offset " + args.input + " by level set, voxel size " +
                  shortNumber(report.json["voxel_size"].get<double>()) + " (" + seconds + ")\n";
  }
  return report;
}

// OUT (with several distances the directory and extension of every offset's file).
std::vector<OutputFile> outputsOfOffset(const OffsetArguments& args) {
  return {{"output", args.output, OutputFormat::MeshOrVdb}};
}

}  // namespace

void addOffsetCommand(CommandRegistry& registry) {
  registry.add<OffsetArguments>(
      {"offset",
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
       "Example: d2vdb offset volumes/ellipsoid.ply out.obj --distance -0.3 --distance 0.25 "
       "--degree 8\n"
       "         d2vdb offset volumes/torus.vdb torus-out.obj --distance 0.1 --patches\n"
       "         d2vdb offset volumes/bunny.vdb bunny-out.obj --distance 0.01 --method levelset",
       "use a lower --degree or fewer --subdivisions; for --method levelset and .vdb outputs a "
       "coarser --voxel-size or --resolution, a smaller --half-width, or a lower --max-voxels to "
       "be refused early",
       declareOffset, runOffset, outputsOfOffset});
}

}  // namespace d2vdb::cli
