// d2vdb smooth: a C-infinity surface (parametric pseudo-manifold) from a closed triangle mesh,
// tessellated watertight, with the surface's normals and optionally its curvatures.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "Command.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/manifold/HalfEdgeMesh.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/PnTriangles.h"
#include "d2vdb/manifold/PseudoManifold.h"
#include "d2vdb/manifold/SmoothTessellation.h"
#include "d2vdb/manifold/SourceDistance.h"
#include "d2vdb/mesh/MeshIO.h"

namespace d2vdb::cli {
namespace {

/// Diverging colour of mean curvature h against `scale`: white at 0, red toward +scale (convex,
/// bending away from the outward normal), blue toward -scale (concave).
std::array<std::uint8_t, 3> meanCurvatureColour(double h, double scale) {
  const double u = scale > 0.0 ? std::clamp(h / scale, -1.0, 1.0) : 0.0;
  const auto channel = [](double value) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 1.0) * 255.0));
  };
  if (u >= 0.0) return {255, channel(1.0 - u), channel(1.0 - u)};
  return {channel(1.0 + u), channel(1.0 + u), 255};
}

/// The value at fraction q (0..1) of the sorted values (nearest rank).
double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const auto index =
      static_cast<std::size_t>(std::clamp(std::ceil(q * static_cast<double>(values.size())) - 1.0,
                                          0.0, static_cast<double>(values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(index),
                   values.end());
  return values[index];
}

/// Unit normals from the file when it has a usable one at every vertex, else nothing.
std::vector<Eigen::Vector3d> fileNormals(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> normals;
  if (!mesh.hasNormals()) return normals;
  for (const Eigen::Vector3f& n : mesh.normals) {
    const Eigen::Vector3d d = n.cast<double>();
    const double length = d.norm();
    if (!(length > 1e-12) || !std::isfinite(length)) return {};
    normals.push_back(d / length);
  }
  return normals;
}

}  // namespace

void addSmoothCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  struct Arguments {
    std::string input, output, source = "loop";
    int lod = 3;
    int maxBidegree = 7;
    bool curvature = false;
  };
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "smooth",
      "Build a smooth (C-infinity) surface from a closed, 2-manifold, consistently oriented\n"
      "triangle mesh (.obj, .ply, .stl) and write it as a watertight triangle mesh with 4^L\n"
      "triangles per input face and the surface's own vertex normals: one chart per vertex,\n"
      "a tensor-product Bezier patch per chart fitted to the source surface (the exact Loop\n"
      "limit surface, or PN triangles), blended with C-infinity weights (Siqueira et al. 2009).\n"
      "--curvature adds per-vertex principal curvatures k1 >= k2 (properties k1, k2) and colours\n"
      "by mean curvature (red convex, white flat, blue concave; scale: 99th percentile of |H|)\n"
      "to .ply output. Reports the distance from the smooth surface to its source.\n"
      "Example: d2vdb smooth volumes/bunny.obj bunny_smooth.ply --lod 3 --curvature");
  command->add_option("input", args->input, "Closed triangle mesh (.obj, .ply, .stl)")->required();
  command->add_option("output", args->output, "Output mesh (.obj, .ply, .stl; written atomically)")
      ->required();
  command->add_option("--source", args->source, "Source surface: loop (default) or pn")
      ->check(CLI::IsMember({"loop", "pn"}));
  command->add_option("--lod", args->lod, "Level of detail L: 4^L triangles per input face")
      ->check(CLI::Range(0, 10))
      ->capture_default_str();
  command
      ->add_option("--max-bidegree", args->maxBidegree,
                   "Cap of the Bezier patches' bidegree min(n + 1, cap) at a vertex of degree n")
      ->check(CLI::Range(2, 12))
      ->capture_default_str();
  command->add_flag("--curvature", args->curvature,
                    "Add k1, k2 and mean-curvature colours (PLY output only)");
  command->add_flag("--json", options.json, "Print the report as JSON on stdout");

  registry.add(command, [args, &options]() {
    const Stopwatch clock;
    const MeshFormat outputFormat = meshFormatFromPath(args->output);
    if (args->curvature && outputFormat != MeshFormat::Ply) {
      throw CLI::ValidationError("--curvature",
                                 "needs a .ply output (OBJ and STL have no "
                                 "per-vertex properties), not " +
                                     args->output);
    }
    LoadOptions load;
    load.purpose = "the input of 'd2vdb smooth'";
    const TriangleMesh input =
        loadInput(args->input, {InputKind::Mesh}, load).take<MeshInput>().mesh;
    std::shared_ptr<const HalfEdgeMesh> mesh;
    try {
      mesh = std::make_shared<const HalfEdgeMesh>(input);
    } catch (const InputError& error) {
      throw InputError(args->input + ": " + error.what());
    }
    checkSmoothTessellation(*mesh, args->lod);  // refuse absurd sizes before any work
    const ProgressCallback progress = makeProgressPrinter(options);

    // The source surface.
    const Stopwatch building;
    std::unique_ptr<SourceSurface> source;
    std::string normalsFrom;
    std::size_t subdividedFaces = 0;
    if (args->source == "loop") {
      auto loop = std::make_unique<LoopLimitSurface>(mesh);
      subdividedFaces = loop->subdividedFaceCount();
      source = std::move(loop);
    } else {
      std::vector<Eigen::Vector3d> normals = fileNormals(input);
      normalsFrom = normals.empty() ? "computed" : "file";
      source = normals.empty() ? std::make_unique<PnTriangles>(mesh)
                               : std::make_unique<PnTriangles>(mesh, std::move(normals));
    }
    PseudoManifoldOptions surfaceOptions;
    surfaceOptions.maxBidegree = args->maxBidegree;
    const PseudoManifold surface(*source, surfaceOptions, progress);
    const double buildSeconds = building.seconds();

    const Stopwatch sampling;
    const SmoothTessellation tessellation = tessellateSmooth(surface, args->lod, args->curvature);
    const double tessellationSeconds = sampling.seconds();

    // Distance to the source at the lattice points (at most 8 intervals per edge).
    const Stopwatch measuring;
    const int distanceSamples = std::min(1 << args->lod, 8);
    const SourceDistanceStatistics distance =
        distanceToSource(surface, *source, std::max(distanceSamples, 1));
    const double distanceSeconds = measuring.seconds();

    nlohmann::json curvatureReport;
    if (args->curvature) {
      const std::size_t count = tessellation.k1.size();
      VertexAttributes attributes;
      std::vector<float> k2(count);
      attributes.scalarName = "k1";
      attributes.scalars.resize(count);
      std::vector<double> mean(count), absMean(count);
      for (std::size_t i = 0; i < count; ++i) {
        attributes.scalars[i] = static_cast<float>(tessellation.k1[i]);
        k2[i] = static_cast<float>(tessellation.k2[i]);
        mean[i] = 0.5 * (tessellation.k1[i] + tessellation.k2[i]);
        absMean[i] = std::abs(mean[i]);
      }
      const double scale = quantile(absMean, 0.99);
      attributes.colours.reserve(count);
      for (const double h : mean) attributes.colours.push_back(meanCurvatureColour(h, scale));
      attributes.moreScalars.push_back({"k2", std::move(k2)});
      writeMesh(args->output, tessellation.mesh, attributes);
      const auto range = [](const std::vector<double>& values) {
        const auto [low, high] = std::minmax_element(values.begin(), values.end());
        return nlohmann::json{{"min", *low}, {"max", *high}};
      };
      curvatureReport = {
          {"k1", range(tessellation.k1)},
          {"k2", range(tessellation.k2)},
          {"mean", range(mean)},
          {"mean_percentiles",
           {{"p1", quantile(mean, 0.01)},
            {"p50", quantile(mean, 0.5)},
            {"p99", quantile(mean, 0.99)}}},
          {"colour_scale", scale},
      };
    } else {
      writeMesh(args->output, tessellation.mesh);
    }

    std::map<int, std::size_t> degrees;
    for (HalfEdgeMesh::Index v = 0; v < mesh->vertexCount(); ++v) {
      if (mesh->degree(v) > 0) ++degrees[mesh->degree(v)];
    }
    nlohmann::json degreeJson = nlohmann::json::object();
    for (const auto& [degree, count] : degrees) degreeJson[std::to_string(degree)] = count;
    const double diagonal = mesh->boundingBoxDiagonal();
    nlohmann::json report = {
        {"input", args->input},
        {"output", args->output},
        {"source", args->source},
        {"lod", args->lod},
        {"max_bidegree", args->maxBidegree},
        {"vertices", mesh->vertexCount()},
        {"faces", mesh->faceCount()},
        {"degrees", degreeJson},
        {"output_vertices", tessellation.mesh.vertexCount()},
        {"output_triangles", tessellation.mesh.triangleCount()},
        {"diagonal", diagonal},
        {"distance_to_source",
         {{"max", distance.maxDistance},
          {"rms", distance.rmsDistance},
          {"max_relative", distance.maxDistance / diagonal},
          {"rms_relative", distance.rmsDistance / diagonal},
          {"parametric_max", distance.maxParametric},
          {"parametric_rms", distance.rmsParametric},
          {"samples", distance.samples},
          {"samples_per_edge", distanceSamples}}},
        {"seconds",
         {{"construction", buildSeconds},
          {"tessellation", tessellationSeconds},
          {"distance", distanceSeconds},
          {"total", clock.seconds()}}},
    };
    if (args->source == "loop") report["subdivided_faces"] = subdividedFaces;
    if (args->source == "pn") report["normals"] = normalsFrom;
    if (args->curvature) report["curvature"] = curvatureReport;

    if (options.json) {
      printJson(report);
      return kSuccess;
    }
    std::string degreeText;
    for (const auto& [degree, count] : degrees) {
      degreeText += (degreeText.empty() ? "" : ", ") + std::to_string(count) + " of degree " +
                    std::to_string(degree);
    }
    status(options, args->input + ": " + std::to_string(mesh->vertexCount()) + " vertices (" +
                        degreeText + "), " + std::to_string(mesh->faceCount()) + " faces");
    if (args->source == "loop" && subdividedFaces > 0) {
      status(options, std::to_string(subdividedFaces) +
                          " faces with two or more extraordinary corners were evaluated on one "
                          "Loop subdivision step");
    }
    char line[256];
    std::snprintf(line, sizeof line,
                  "distance to the %s source: max %.3g (%.3g of the diagonal), RMS %.3g, at %zu "
                  "samples",
                  args->source == "loop" ? "Loop limit" : "PN triangle", distance.maxDistance,
                  distance.maxDistance / diagonal, distance.rmsDistance, distance.samples);
    status(options, line);
    if (args->curvature) {
      std::snprintf(
          line, sizeof line, "curvature: k1 %.4g .. %.4g, k2 %.4g .. %.4g, mean %.4g .. %.4g",
          curvatureReport["k1"]["min"].get<double>(), curvatureReport["k1"]["max"].get<double>(),
          curvatureReport["k2"]["min"].get<double>(), curvatureReport["k2"]["max"].get<double>(),
          curvatureReport["mean"]["min"].get<double>(),
          curvatureReport["mean"]["max"].get<double>());
      status(options, line);
    }
    status(options, "wrote " + args->output + ": " +
                        std::to_string(tessellation.mesh.vertexCount()) + " vertices, " +
                        std::to_string(tessellation.mesh.triangleCount()) + " triangles, " +
                        std::to_string(clock.seconds()) + " s");
    return kSuccess;
  });
}

// TRANSITION: the old registration until this command has its CommandDefinition.
void addSmoothCommand(CommandRegistry& registry) {
  addSmoothCommand(registry.app(), registry, registry.legacyOptions());
}

}  // namespace d2vdb::cli
