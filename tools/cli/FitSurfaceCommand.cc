// d2vdb fit-surface: fits a tensor-product B-spline surface to a distance field (.vdb), an exact
// B-spline surface (.json) or a point cloud (.xyz/.ply) by squared distance minimisation (PDM,
// TDM, SDM, TDM+PDM; Pottmann, Leopoldseder and Hofer 2002), optionally a ruled surface or an
// offset, and writes the surface, a tessellated mesh coloured by the distance, the rulings and
// the convergence plot.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "CertifiedFitError.h"
#include "Command.h"
#include "ConvergencePlot.h"
#include "FitReports.h"
#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/AtomicFileSet.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/fit/InitialSurface.h"
#include "d2vdb/fit/RuledSurface.h"
#include "d2vdb/fit/SurfaceFitter.h"
#include "d2vdb/io/FitTarget.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/measure/PointSetDistance.h"
#include "d2vdb/mesh/DistanceColors.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/SurfaceTessellation.h"

namespace d2vdb::cli {
namespace {

struct FitSurfaceArguments {
  std::string target, init = "plane", method = "sdm", out, mesh, plot, rulings;
  std::vector<int> degree{3, 3};
  std::vector<int> controlPoints{8, 8};
  bool closedU = false, closedV = false, ruled = false;
  double offset = 0.0;
  double certify = 0.0;  ///< --certify: relative bracket width, 0 for none
  int meshSamples = 8;
  int rulingSamples = 4;
  bool plainSdm = false;
  bool noRestart = false;
  SurfaceFitOptions fit;
};

BSplineSurface initialSurface(const FitSurfaceArguments& args, const FitTarget& target,
                              bool& ruled) {
  if (args.init != "plane" && args.init != "cylinder" && args.init != "torus") {
    LoadOptions load;
    load.purpose = "the initial surface (--init)";
    const BSplineSurface surface = loadInputAs<BSplineSurface>(args.init, load);
    ruled = surface.degreeU() == 1;
    return surface;
  }
  SurfaceLayout layout;
  layout.degreeU = args.ruled ? 1 : args.degree[0];
  layout.degreeV = args.degree[1];
  layout.countU = args.controlPoints[0];
  layout.countV = args.controlPoints[1];
  layout.closedU = args.closedU;
  layout.closedV = args.closedV;
  ruled = layout.degreeU == 1;
  return initialSurfaceForTarget(target, args.init, layout, args.offset);
}

/// Signed or unsigned distance from a point to the fitted target, for the mesh and the rulings:
/// the nearest data point of a cloud, the target's distance elsewhere (NaN outside its domain).
std::function<double(const Eigen::Vector3d&)> distanceFunction(const FitTarget& target) {
  if (target.kind == InputKind::PointSet) {
    auto cloud = std::make_shared<const PointSetDistance>(target.points);
    return [cloud](const Eigen::Vector3d& x) { return (*cloud)(x); };
  }
  const SquaredDistanceTarget& fitTarget = target.fitTarget();
  const Eigen::AlignedBox3d domain = fitTarget.domain();
  return [&fitTarget, domain](const Eigen::Vector3d& x) {
    if (!domain.contains(x)) return std::numeric_limits<double>::quiet_NaN();
    const Approximant a = fitTarget.approximantAt(x);
    return a.kind == TargetKind::Surface ? a.distance : std::sqrt(a.form(ErrorTerm::SDM)(x));
  };
}

// The progress stage of writing the --mesh output, whose vertices' distances to the target take
// most of the time after the fit.
constexpr const char* kMeshStage = "writing --mesh (distances to the target)";

// The --mesh grid: `samples` vertices per control point in each direction.
std::array<int, 2> meshSamples(const BSplineSurface& surface, int samples) {
  return {std::max(surface.isClosedU() ? 3 : 2, samples * surface.countU()),
          std::max(surface.isClosedV() ? 3 : 2, samples * surface.countV())};
}

nlohmann::json writeSurfaceMesh(const std::string& file, const std::string& target,
                                const BSplineSurface& surface, int samples,
                                const std::function<double(const Eigen::Vector3d&)>& distance,
                                const ProgressCallback& progress) {
  const auto [samplesU, samplesV] = meshSamples(surface, samples);
  const TriangleMesh mesh = tessellate(surface, samplesU, samplesV);
  double largest = 0.0;
  if (progress) progress(kMeshStage, 0.0);
  std::size_t done = 0;
  const double count = static_cast<double>(mesh.vertexCount());
  const auto counted = [&](const Eigen::Vector3d& x) {
    if (progress && ++done % 1024 == 0) progress(kMeshStage, 0.99 * done / count);
    return distance(x);
  };
  writeMesh(file, mesh, distanceAttributes(mesh, counted, largest));
  if (progress) progress(kMeshStage, 1.0);
  return {{"file", target},
          {"vertices", mesh.vertexCount()},
          {"triangles", mesh.triangleCount()},
          {"max_distance", largest}};
}

// What one ruling costs in the --rulings file (dump(1): eight numbers of up to 24 characters,
// the keys and the indentation; 278 bytes measured on average) and in memory while the JSON
// document is built (its nodes and the dumped text: 1.95 kB measured, 'fit-surface --ruled
// --ctrl 20,20 --ruling-samples 1000', 323,342 rulings, 700 MB peak).
constexpr double kRulingFileBytes = 330.0;
constexpr double kRulingMemoryBytes = 2500.0;

nlohmann::json writeRulings(const std::string& file, const std::string& target,
                            const BSplineSurface& surface, int samples,
                            const std::function<double(const Eigen::Vector3d&)>& distance) {
  const std::vector<Ruling> rulings = surfaceRulings(surface, samples);
  nlohmann::json list = nlohmann::json::array();
  double worst = 0.0;
  for (const Ruling& ruling : rulings) {
    double largest = 0.0;
    for (int i = 0; i <= 64; ++i) {
      const double d = distance(ruling.start + (ruling.end - ruling.start) * (i / 64.0));
      if (std::isfinite(d)) largest = std::max(largest, std::abs(d));
    }
    worst = std::max(worst, largest);
    list.push_back({{"v", ruling.v},
                    {"piece", ruling.piece},
                    {"start", {ruling.start.x(), ruling.start.y(), ruling.start.z()}},
                    {"end", {ruling.end.x(), ruling.end.y(), ruling.end.z()}},
                    {"max_distance", largest}});
  }
  const nlohmann::json document = {{"type", "rulings"},
                                   {"version", 1},
                                   {"samples_per_span", samples},
                                   {"max_distance", worst},
                                   {"rulings", list}};
  writeStreamAtomically(file, [&](std::ostream& out) { out << document.dump(1) << '\n'; });
  return {{"file", target}, {"count", rulings.size()}, {"max_distance", worst}};
}

void declareFitSurfaceShape(CLI::App& command, FitSurfaceArguments& args) {
  command
      .add_option("--init", args.init,
                  "Initial surface: plane (sheet over the target's principal plane), cylinder "
                  "(closed around its axis), torus (closed in both), or a surface .json")
      ->capture_default_str();
  command.add_option("--method", args.method, "pdm, tdm, sdm or tdm+pdm")->capture_default_str();
  command.add_option("--degree", args.degree, "Degrees p,q of a generated initial surface")
      ->delimiter(',')
      ->expected(2)
      ->capture_default_str();
  command.add_option("--ctrl", args.controlPoints, "Control points m,n of a generated surface")
      ->delimiter(',')
      ->expected(2)
      ->capture_default_str();
  command.add_flag("--closed-u", args.closedU, "Closed (periodic) in u");
  command.add_flag("--closed-v", args.closedV, "Closed (periodic) in v");
  command.add_flag("--ruled", args.ruled,
                   "Ruled surface: degree 1 in u (straight rulings along u), degree q in v");
  command.add_option("--offset", args.offset,
                     "Fit the offset at this distance (negative: inward; field or surface target)");
}

void declareFitSurfaceOutputs(CLI::App& command, FitSurfaceArguments& args) {
  command.add_option("--out", args.out, "Write the fitted surface (.json)")->required();
  command.add_option("--mesh", args.mesh,
                     "Write a tessellation (.obj/.ply; PLY with a per-vertex 'distance' and "
                     "colours: blue inside, white on, red outside the target)");
  command.add_option("--mesh-samples", args.meshSamples, "Mesh vertices per control point")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  command.add_option("--rulings", args.rulings,
                     "With a ruled surface: write its rulings (.json) with their distances");
  command
      .add_option("--ruling-samples", args.rulingSamples,
                  "Rulings per knot span besides "
                  "the knots")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  command.add_option("--plot", args.plot, "Plot the RMS distance per iteration (SVG)");
  declareCertifyOption(command, args.certify);
}

void declareFitSurface(CLI::App& command, FitSurfaceArguments& args) {
  command
      .add_option("--target", args.target,
                  "Target: .vdb level set or field, surface .json, "
                  ".xyz/.ply point cloud")
      ->required();
  declareFitSurfaceShape(command, args);
  declareFitSurfaceOutputs(command, args);
  command
      .add_option("--sensors", args.fit.sensorsPerSpan,
                  "Sensors per knot span and direction (SDM I)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  declareFitOptions(command, args.fit, args.plainSdm,
                    {"surface", "Thin-plate weight (dimensionless; default: automatic, see README)",
                     "Membrane weight (dimensionless)",
                     "SDM without the exact second-order terms (for comparison)"});
  command.add_flag("--no-restart", args.noRestart,
                   "Field and surface targets: no re-parametrisation by chord length and restart "
                   "(for comparison)");
}

SurfaceFitResult runFit(const FitSurfaceArguments& args, FitMethod method,
                        const BSplineSurface& initial, const FitTarget& target,
                        const CommandContext& context) {
  SurfaceFitOptions fit = args.fit;
  fit.method = method;
  fit.exactSecondOrder = !args.plainSdm;
  fit.reparametrize = !args.noRestart;
  fit.progress = context.progress();
  fit.budget = context.options().budget;
  return target.kind == InputKind::PointSet ? fitSurfaceToPoints(initial, target.points, fit)
                                            : fitSurface(initial, target.fitTarget(), fit);
}

// The estimated bytes written and the memory of writing them (the mesh, the rulings' JSON
// document) for `meshSamples` and `rulingSamples` (the fit keeps the initial surface's knots, so
// its grid and rulings are known before the fit).
struct OutputEstimate {
  double fileBytes = 0.0;
  double memoryBytes = 0.0;
};

OutputEstimate estimateFitSurfaceOutputs(const FitSurfaceArguments& args,
                                         const BSplineSurface& initial, int meshSamplesPerPoint,
                                         int rulingSamples) {
  OutputEstimate estimate;
  estimate.fileBytes = 4096.0 + 100.0 * static_cast<double>(initial.controlPoints().size()) +
                       25.0 * (initial.countU() + initial.countV());
  if (!args.mesh.empty()) {
    const auto [samplesU, samplesV] = meshSamples(initial, meshSamplesPerPoint);
    const double vertices = static_cast<double>(samplesU) * samplesV;
    const double triangles = 2.0 * vertices;
    MeshFileContents contents;
    contents.normals = contents.colors = true;
    contents.scalars = 1;
    estimate.fileBytes +=
        estimateMeshFileBytes(meshFormatFromPath(args.mesh), vertices, triangles, contents);
    // Positions, normals, distances, colours; triangles; the attribute copies.
    estimate.memoryBytes += vertices * (24.0 + 8.0 + 8.0 + 3.0) + triangles * 12.0;
  }
  if (!args.rulings.empty() && initial.degreeU() == 1) {
    const double rulings = surfaceRulingCount(initial, rulingSamples);
    estimate.fileBytes += kRulingFileBytes * rulings;
    estimate.memoryBytes += (kRulingMemoryBytes + kRulingFileBytes) * rulings;
  }
  return estimate;
}

// Refuses, before the fit, outputs whose size or memory would exceed the budget, naming the
// largest --mesh-samples and --ruling-samples that would fit.
void checkFitSurfaceOutputs(const FitSurfaceArguments& args, const BSplineSurface& initial,
                            const ResourceBudget& budget) {
  const auto fits = [&](int mesh, int rulings) {
    const OutputEstimate e = estimateFitSurfaceOutputs(args, initial, mesh, rulings);
    return (budget.maxOutputBytes == 0 || e.fileBytes <= double(budget.maxOutputBytes)) &&
           (budget.maxMemoryBytes == 0 || e.memoryBytes <= double(budget.maxMemoryBytes));
  };
  if (fits(args.meshSamples, args.rulingSamples)) return;
  const bool withRulings = !args.rulings.empty() && initial.degreeU() == 1;
  std::vector<std::string> remedies;
  if (withRulings) {
    const long long rulings = largestFitting(0, args.rulingSamples, [&](long long r) {
      return fits(args.meshSamples, static_cast<int>(r));
    });
    if (rulings >= 0) remedies.push_back("--ruling-samples " + std::to_string(rulings));
  }
  if (!args.mesh.empty()) {
    const long long mesh = largestFitting(1, args.meshSamples, [&](long long m) {
      return fits(static_cast<int>(m), args.rulingSamples);
    });
    if (mesh >= 1) remedies.push_back("--mesh-samples " + std::to_string(mesh));
  }
  std::string remedy = "use fewer control points (--ctrl)";
  if (!remedies.empty()) {
    remedy = "use " + remedies.front();
    for (std::size_t i = 1; i < remedies.size(); ++i) remedy += " or " + remedies[i];
    remedy += " or less, or fewer control points (--ctrl)";
  }
  std::string subject = "the outputs of a surface of " + std::to_string(initial.countU()) + " x " +
                        std::to_string(initial.countV()) + " control points";
  if (!args.mesh.empty()) {
    const auto [samplesU, samplesV] = meshSamples(initial, args.meshSamples);
    subject += ", a --mesh of " + std::to_string(samplesU) + " x " + std::to_string(samplesV) +
               " vertices (--mesh-samples " + std::to_string(args.meshSamples) + ")";
  }
  if (withRulings) {
    subject +=
        ", " +
        std::to_string(static_cast<long long>(surfaceRulingCount(initial, args.rulingSamples))) +
        " --rulings (--ruling-samples " + std::to_string(args.rulingSamples) + ")";
  }
  const OutputEstimate estimate =
      estimateFitSurfaceOutputs(args, initial, args.meshSamples, args.rulingSamples);
  enforceOutputBudget({subject, estimate.fileBytes, remedy}, budget);
  enforceMemoryBudget({"writing " + subject, estimate.memoryBytes, remedy}, budget);
}

// The surface, the mesh, the rulings and the plot, each with its entry of the report; each
// output a progress stage of its own ("writing --mesh ..."). All are written to temporary names
// and replace their targets only when every one of them has been written.
void writeFitSurfaceOutputs(const FitSurfaceArguments& args, FitMethod method,
                            const FitTarget& target, const SurfaceFitResult& result,
                            const ProgressCallback& progress, nlohmann::json& report) {
  const auto distance = distanceFunction(target);
  AtomicFileSet files;
  if (progress) progress("writing --out", 0.0);
  files.stage(args.out, [&](const std::filesystem::path& temporary) {
    writeSurfaceJson(temporary, result.surface);
  });
  if (progress) progress("writing --out", 1.0);
  if (!args.mesh.empty()) {
    files.stage(args.mesh, [&](const std::filesystem::path& temporary) {
      report["mesh"] = writeSurfaceMesh(temporary.string(), args.mesh, result.surface,
                                        args.meshSamples, distance, progress);
    });
  }
  if (!args.rulings.empty()) {
    if (progress) progress("writing --rulings", 0.0);
    files.stage(args.rulings, [&](const std::filesystem::path& temporary) {
      report["rulings"] = writeRulings(temporary.string(), args.rulings, result.surface,
                                       args.rulingSamples, distance);
    });
    if (progress) progress("writing --rulings", 1.0);
  }
  if (!args.plot.empty()) {
    files.stage(args.plot, [&](const std::filesystem::path& temporary) {
      writeConvergencePlot(temporary.string(),
                           {{method, &result.history, result.iterations(), result.status}},
                           "fit-surface");
    });
    report["plot"] = args.plot;
  }
  files.commit();
}

Report runFitSurface(const FitSurfaceArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  const FitMethod method = parseFitMethod(args.method);
  if (!std::isfinite(args.offset)) throw InputError("--offset must be a finite number");
  checkInitOption(args.init, {"plane", "cylinder", "torus"}, "a B-spline surface .json");
  FitTargetOptions load;
  load.spline = FitSpline::Surface;
  load.offset = args.offset;
  load.purpose = "the target of 'd2vdb fit-surface'";
  load.progress = context.progress();
  const FitTarget target = loadFitTarget(args.target, load);
  const std::optional<HausdorffInput> certifyAgainst =
      certifyTarget(args.target, args.certify, args.offset, context);
  bool ruled = false;
  const BSplineSurface initial = initialSurface(args, target, ruled);
  if (!args.rulings.empty() && !ruled) {
    throw InputError(
        "--rulings needs a ruled surface (--ruled, or an initial surface of degree "
        "1 in u)");
  }
  const ResourceBudget& budget = context.options().budget;
  checkFitSurfaceOutputs(args, initial, budget);
  const SurfaceFitResult result = runFit(args, method, initial, target, context);

  nlohmann::json json = fitReportJson(result, method);
  json.update({{"target", args.target},
               {"target_kind", inputKindName(target.kind)},
               {"offset", args.offset},
               {"dimension", 3},
               {"degree", {initial.degreeU(), initial.degreeV()}},
               {"control_points", {initial.countU(), initial.countV()}},
               {"closed", {initial.isClosedU(), initial.isClosedV()}},
               {"ruled", ruled},
               {"output", args.out}});
  std::string text = fitReportText(result, method);
  if (certifyAgainst) {
    std::string line;
    json["certified"] = certifiedFitError(hausdorffInputOfSurface(result.surface), *certifyAgainst,
                                          args.certify, context, line);
    text += line;
  }
  writeFitSurfaceOutputs(args, method, target, result, context.progress(), json);
  return fitAnswer(std::move(json), std::move(text), clock.seconds(), args.out, context);
}

std::vector<OutputFile> outputsOfFitSurface(const FitSurfaceArguments& args) {
  return {{"--out", args.out, OutputFormat::Json},
          {"--mesh", args.mesh, OutputFormat::ObjOrPly,
           "its vertices carry the distance to the target, which STL cannot hold"},
          {"--rulings", args.rulings, OutputFormat::Json},
          {"--plot", args.plot, OutputFormat::Svg}};
}

}  // namespace

void addFitSurfaceCommand(CommandRegistry& registry) {
  registry.add<FitSurfaceArguments>(
      {"fit-surface",
       "Fit a tensor-product B-spline surface (knots fixed; open or closed in u and v; ruled with "
       "--ruled) to a level set / field .vdb (SDM I), a B-spline surface .json (exact, SDM I) or "
       "a point cloud .xyz/.ply (SDM II: errors orthogonal to the active surface). Prints the "
       "iteration history and why it stopped.\n"
       "Example: d2vdb fit-surface --target volumes/torus.vdb --init torus --ctrl 12,8 "
       "--out torus.json --mesh torus.ply --plot conv.svg",
       "use fewer control points (--ctrl) or sensors (--sensors), or a smaller target",
       declareFitSurface, runFitSurface, outputsOfFitSurface});
}

}  // namespace d2vdb::cli
