// d2vdb smooth: a C-infinity surface (parametric pseudo-manifold) from a closed triangle mesh,
// tessellated watertight, with the surface's normals and optionally its curvatures.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "Command.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/manifold/SmoothSurfaceFromMesh.h"
#include "d2vdb/manifold/SmoothTessellation.h"
#include "d2vdb/manifold/SourceDistance.h"
#include "d2vdb/mesh/CurvatureColors.h"
#include "d2vdb/mesh/MeshIO.h"

namespace d2vdb::cli {
namespace {

struct SmoothArguments {
  std::string input, output, source = "loop";
  int lod = 3;
  int maxBidegree = 7;
  bool curvature = false;
};

void declareSmooth(CLI::App& command, SmoothArguments& args) {
  command.add_option("input", args.input, "Closed triangle mesh (.obj, .ply, .stl)")->required();
  command.add_option("output", args.output, "Output mesh (.obj, .ply, .stl; written atomically)")
      ->required();
  command.add_option("--source", args.source, "Source surface: loop (default) or pn")
      ->check(CLI::IsMember({"loop", "pn"}));
  command.add_option("--lod", args.lod, "Level of detail L: 4^L triangles per input face")
      ->check(CLI::Range(0, 10))
      ->capture_default_str();
  command
      .add_option("--max-bidegree", args.maxBidegree,
                  "Cap of the Bezier patches' bidegree min(n + 1, cap) at a vertex of degree n")
      ->check(CLI::Range(2, 12))
      ->capture_default_str();
  command.add_flag("--curvature", args.curvature,
                   "Add k1, k2 and mean-curvature colours (PLY output only)");
}

/// Writes the tessellation with per-vertex k1, k2 and mean-curvature colours (PLY) and returns
/// the "curvature" report: ranges, percentiles of the mean curvature and the colour scale.
nlohmann::json writeCurvatureMesh(const std::string& file, const SmoothTessellation& tessellation) {
  const CurvatureAttributes curvature = curvatureAttributes(tessellation.k1, tessellation.k2);
  writeMesh(file, tessellation.mesh, curvature.attributes);
  const CurvatureSummary& summary = curvature.summary;
  const auto range = [](const std::array<double, 2>& values) {
    return nlohmann::json{{"min", values[0]}, {"max", values[1]}};
  };
  return {
      {"k1", range(summary.k1Range)},
      {"k2", range(summary.k2Range)},
      {"mean", range(summary.meanRange)},
      {"mean_percentiles",
       {{"p1", summary.meanPercentiles[0]},
        {"p50", summary.meanPercentiles[1]},
        {"p99", summary.meanPercentiles[2]}}},
      {"colour_scale", summary.colorScale},
  };
}

/// How many vertices have each degree (unused vertices left out).
std::map<int, std::size_t> degreeCounts(const HalfEdgeMesh& mesh) {
  std::map<int, std::size_t> degrees;
  for (HalfEdgeMesh::Index v = 0; v < mesh.vertexCount(); ++v) {
    if (mesh.degree(v) > 0) ++degrees[mesh.degree(v)];
  }
  return degrees;
}

/// What runSmooth() measured, for the report.
struct SmoothResult {
  MeshSmoothSurface smooth;
  SmoothTessellation tessellation;
  SourceDistanceStatistics distance;
  MeshDeviationStatistics meshDistance;  // from the smooth surface to the input mesh
  int distanceSamples = 0;
  nlohmann::json curvature;  // with --curvature
  double tessellationSeconds = 0, distanceSeconds = 0;
};

nlohmann::json smoothJson(const SmoothArguments& args, const SmoothResult& result,
                          const std::map<int, std::size_t>& degrees, double totalSeconds) {
  const HalfEdgeMesh& mesh = *result.smooth.mesh;
  const SourceDistanceStatistics& distance = result.distance;
  nlohmann::json degreeJson = nlohmann::json::object();
  for (const auto& [degree, count] : degrees) degreeJson[std::to_string(degree)] = count;
  const double diagonal = mesh.boundingBoxDiagonal();
  nlohmann::json json = {
      {"input", args.input},
      {"output", args.output},
      {"source", args.source},
      {"lod", args.lod},
      {"max_bidegree", args.maxBidegree},
      {"vertices", mesh.vertexCount()},
      {"faces", mesh.faceCount()},
      {"degrees", degreeJson},
      {"output_vertices", result.tessellation.mesh.vertexCount()},
      {"output_triangles", result.tessellation.mesh.triangleCount()},
      {"diagonal", diagonal},
      {"distance_to_source",
       {{"max", distance.maxDistance},
        {"rms", distance.rmsDistance},
        {"max_relative", distance.maxDistance / diagonal},
        {"rms_relative", distance.rmsDistance / diagonal},
        {"parametric_max", distance.maxParametric},
        {"parametric_rms", distance.rmsParametric},
        {"samples", distance.samples},
        {"samples_per_edge", result.distanceSamples}}},
      {"distance_to_mesh",
       {{"max", result.meshDistance.maxDistance},
        {"rms", result.meshDistance.rmsDistance},
        {"max_relative", result.meshDistance.maxDistance / diagonal},
        {"rms_relative", result.meshDistance.rmsDistance / diagonal},
        {"samples", result.meshDistance.samples},
        {"samples_per_edge", result.distanceSamples}}},
      {"seconds",
       {{"construction", result.smooth.buildSeconds},
        {"tessellation", result.tessellationSeconds},
        {"distance", result.distanceSeconds},
        {"total", totalSeconds}}},
  };
  if (args.source == "loop") json["subdivided_faces"] = result.smooth.subdividedFaces;
  if (args.source == "pn") json["normals"] = result.smooth.normalsFromFile ? "file" : "computed";
  if (args.curvature) json["curvature"] = result.curvature;
  return json;
}

std::string smoothText(const SmoothArguments& args, const SmoothResult& result,
                       const std::map<int, std::size_t>& degrees, double totalSeconds) {
  const HalfEdgeMesh& mesh = *result.smooth.mesh;
  std::string degreeText;
  for (const auto& [degree, count] : degrees) {
    degreeText += (degreeText.empty() ? "" : ", ") + std::to_string(count) + " of degree " +
                  std::to_string(degree);
  }
  std::string text = args.input + ": " + std::to_string(mesh.vertexCount()) + " vertices (" +
                     degreeText + "), " + std::to_string(mesh.faceCount()) + " faces\n";
  if (args.source == "loop" && result.smooth.subdividedFaces > 0) {
    text += std::to_string(result.smooth.subdividedFaces) +
            " faces with two or more extraordinary corners were evaluated on one Loop "
            "subdivision step\n";
  }
  const SourceDistanceStatistics& distance = result.distance;
  const double diagonal = mesh.boundingBoxDiagonal();
  char line[256];
  std::snprintf(line, sizeof line,
                "distance to the %s source: max %.3g (%.3g of the diagonal), RMS %.3g, at %zu "
                "samples\n",
                args.source == "loop" ? "Loop limit" : "PN triangle", distance.maxDistance,
                distance.maxDistance / diagonal, distance.rmsDistance, distance.samples);
  text += line;
  const MeshDeviationStatistics& toMesh = result.meshDistance;
  std::snprintf(line, sizeof line,
                "distance to the input mesh: max %.3g (%.3g of the diagonal), RMS %.3g, at the "
                "same samples\n",
                toMesh.maxDistance, toMesh.maxDistance / diagonal, toMesh.rmsDistance);
  text += line;
  if (args.curvature) {
    const nlohmann::json& curvature = result.curvature;
    std::snprintf(line, sizeof line,
                  "curvature: k1 %.4g .. %.4g, k2 %.4g .. %.4g, mean %.4g .. %.4g\n",
                  curvature["k1"]["min"].get<double>(), curvature["k1"]["max"].get<double>(),
                  curvature["k2"]["min"].get<double>(), curvature["k2"]["max"].get<double>(),
                  curvature["mean"]["min"].get<double>(), curvature["mean"]["max"].get<double>());
    text += line;
  }
  text += "wrote " + args.output + ": " + std::to_string(result.tessellation.mesh.vertexCount()) +
          " vertices, " + std::to_string(result.tessellation.mesh.triangleCount()) +
          " triangles, " + std::to_string(totalSeconds) + " s\n";
  return text;
}

MeshSmoothSurface buildSmoothSurface(const SmoothArguments& args, const TriangleMesh& input,
                                     const CommandContext& context) {
  SmoothSurfaceFromMeshOptions options;
  options.source =
      args.source == "loop" ? SmoothSurfaceSource::LoopLimit : SmoothSurfaceSource::PnTriangles;
  options.fileNormals = true;
  options.surface.maxBidegree = args.maxBidegree;
  options.label = args.input;
  const int lod = args.lod;
  const bool curvature = args.curvature;
  const MeshFormat format = meshFormatFromPath(args.output);
  const ResourceBudget budget = context.options().budget;
  options.beforeBuilding = [lod, curvature, format, budget](const HalfEdgeMesh& mesh) {
    // Refuse absurd sizes before any work.
    checkSmoothTessellation(mesh, lod);
    enforceSmoothTessellationBudget(mesh, lod, curvature, format, budget);
  };
  return smoothSurfaceFromMesh(input, options, context.progress());
}

Report runSmooth(const SmoothArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  LoadOptions load;
  load.purpose = "the input of 'd2vdb smooth'";
  const TriangleMesh input = loadInput(args.input, {InputKind::Mesh}, load).take<MeshInput>().mesh;
  SmoothResult result{buildSmoothSurface(args, input, context), {}, {}, {}, 0, {}, 0, 0};
  const PseudoManifold& surface = result.smooth.surface;

  const Stopwatch sampling;
  result.tessellation = tessellateSmooth(surface, args.lod, args.curvature);
  result.tessellationSeconds = sampling.seconds();

  // Distance to the source at the lattice points (at most 8 intervals per edge).
  const Stopwatch measuring;
  result.distanceSamples = std::min(1 << args.lod, 8);
  result.distance =
      distanceToSource(surface, *result.smooth.source, std::max(result.distanceSamples, 1));
  result.meshDistance =
      distanceToMesh(surface, MeshDistance(input), std::max(result.distanceSamples, 1));
  result.distanceSeconds = measuring.seconds();

  if (args.curvature) {
    result.curvature = writeCurvatureMesh(args.output, result.tessellation);
  } else {
    writeMesh(args.output, result.tessellation.mesh);
  }

  const std::map<int, std::size_t> degrees = degreeCounts(*result.smooth.mesh);
  Report report;
  report.json = smoothJson(args, result, degrees, clock.seconds());
  report.text = smoothText(args, result, degrees, clock.seconds());
  return report;
}

std::vector<OutputFile> outputsOfSmooth(const SmoothArguments& args) {
  if (args.curvature) {
    return {{"output", args.output, OutputFormat::Ply,
             "--curvature adds per-vertex properties, which OBJ and STL cannot hold"}};
  }
  return {{"output", args.output, OutputFormat::Mesh}};
}

}  // namespace

void addSmoothCommand(CommandRegistry& registry) {
  registry.add<SmoothArguments>(
      {"smooth",
       "Build a smooth (C-infinity) surface from a closed, 2-manifold, consistently oriented\n"
       "triangle mesh (.obj, .ply, .stl) and write it as a watertight triangle mesh with 4^L\n"
       "triangles per input face and the surface's own vertex normals: one chart per vertex,\n"
       "a tensor-product Bezier patch per chart fitted to the source surface (the exact Loop\n"
       "limit surface, or PN triangles), blended with C-infinity weights (Siqueira et al. 2009).\n"
       "--curvature adds per-vertex principal curvatures k1 >= k2 (properties k1, k2) and colours\n"
       "by mean curvature (red convex, white flat, blue concave; scale: 99th percentile of |H|)\n"
       "to .ply output. Reports the distance from the smooth surface to its source and to the "
       "input mesh.\n"
       "Example: d2vdb smooth volumes/bunny.obj bunny_smooth.ply --lod 3 --curvature",
       "use a lower --lod or --max-bidegree, or a smaller mesh", declareSmooth, runSmooth,
       outputsOfSmooth});
}

}  // namespace d2vdb::cli
