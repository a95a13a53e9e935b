#include "SupportInputs.h"

#include <openvdb/openvdb.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <utility>

#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/support/SupportMeasures.h"

namespace d2vdb::cli {
namespace {

// A number for JSON, with null for +-infinity (JSON has none): an unbounded side of a range.
nlohmann::json finiteOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace

OrientedSamples samplesFromField(const ApproximantField& field, const std::string& source) {
  if (field.kind() != TargetKind::Surface) {
    throw InputError("'" + source + "' is a field of a " + targetKindName(field.kind()) +
                     ", not of a surface: a support function needs a closed surface");
  }
  const openvdb::FloatGrid::ConstPtr grid = field.distanceGrid();
  const double limit = 0.5 * field.voxelSize();
  ApproximantField::Accessor accessor(field);
  OrientedSamples samples;
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    if (std::abs(static_cast<double>(*it)) > limit) continue;
    const openvdb::Vec3d world = grid->indexToWorld(it.getCoord());
    const Approximant a = accessor.approximantAt(Eigen::Vector3d(world.x(), world.y(), world.z()));
    if ((a.flags & kFlagCutLocus) != 0) continue;
    samples.points.push_back(a.footpoint);
    samples.normals.push_back(a.normal);
  }
  if (samples.points.empty()) {
    throw InputError("'" + source + "' has no band voxels within half a voxel of its surface");
  }
  return samples;
}

SupportInput loadSupportInput(const std::string& path, const GlobalOptions& options) {
  SupportInput input;
  if (isSupportFunctionFile(path)) {
    input.kind = "support function";
    input.document = readSupportFunctionJson(path);
    return input;
  }
  LoadOptions load;
  load.purpose =
      "a support function's input (a mesh, a point set with normals as a .ply, a level set, a "
      "field, or a support-function .json)";
  load.progress = makeProgressPrinter(options);
  // Without PointSet among the accepted kinds, a PLY without faces comes as a mesh of its
  // vertices, normals included.
  LoadedInput loaded = loadInput(path, {InputKind::Mesh, InputKind::Field}, load);
  if (loaded.kind() == InputKind::Field) {
    const FieldInput field = std::move(loaded).take<FieldInput>();
    input.samples = samplesFromField(field.field, path);
    input.kind = field.stored ? "field" : "level set";
    return input;
  }
  const TriangleMesh mesh = std::move(loaded).take<MeshInput>().mesh;
  if (mesh.triangles.empty()) {
    input.kind = "points";
    input.samples = samplesFromMesh(mesh, "'" + path + "'");
    return input;
  }
  MeshGaussImage image = meshGaussImage(mesh, "'" + path + "'");
  input.samples = image.samples;
  input.kind = image.closed ? "mesh" : "mesh patch";
  if (!image.closed) input.patch = image.gaussImage;
  if (!mesh.hasNormals()) {
    input.warnings.push_back("'" + path +
                             "' has no vertex normals: using area-weighted normals of its "
                             "triangles, which limit the fit's accuracy to the facets' size");
  }
  input.gaussImage = std::move(image);
  return input;
}

SphericalTriangulation validityDomain(const SupportFunctionDocument& document) {
  return document.patch ? *document.patch : validationSphere(document.function.degree());
}

CheckedSupport fitAndCheck(const SupportInput& input, const std::string& source, int degree,
                           double regularization, bool allowSingular) {
  CheckedSupport checked;
  if (input.document) {
    checked.document = *input.document;
  } else {
    SupportFitOptions fitOptions;
    fitOptions.degree = degree;
    fitOptions.regularization = regularization >= 0.0 ? regularization
                                : input.patch         ? kPatchSupportRegularization
                                                      : kDefaultSupportRegularization;
    SupportFitReport report;
    checked.document.function =
        fitSupportFunction(input.samples, fitOptions, &report, "'" + source + "'");
    checked.document.patch = input.patch;
    checked.document.fit =
        SupportFitRecord{std::filesystem::path(source).filename().string(), report.samples,
                         report.regularization, report.rmsResidual, report.maxResidual};
    if (report.renormalisedNormals > 0) {
      checked.warnings.push_back(std::to_string(report.renormalisedNormals) +
                                 " sample normals were not unit length (off by up to " +
                                 formatNumber(report.largestNormalDeviation, 6) +
                                 ") and were normalised");
    }
    checked.fit = report;
  }
  checked.validity =
      analyzeSupportValidity(checked.document.function, validityDomain(checked.document));
  // A fit that misses its samples badly is no representation of the input even when it is regular
  // (e.g. a torus over the whole sphere averages its outer and inner halves into a sphere).
  const double relativeResidual =
      checked.fit && checked.fit->size > 0.0 ? checked.fit->maxResidual / checked.fit->size : 0.0;
  const bool missed = relativeResidual > kMaxRelativeSupportResidual;
  if (!checked.validity.regular() || missed) {
    std::string why =
        "'" + source + "': the support function is " + checked.validity.describe() +
        (missed
             ? " but misses the samples by up to " + formatNumber(checked.fit->maxResidual, 4) +
                   " (" + formatNumber(100.0 * relativeResidual, 3) + "% of the size, more than " +
                   formatNumber(100.0 * kMaxRelativeSupportResidual, 3) + "%)"
             : std::string()) +
        ". ";
    if (input.gaussImage && input.gaussImage->reversingTriangles > 0 &&
        input.gaussImage->preservingTriangles > 0) {
      why += "Of its " +
             std::to_string(input.gaussImage->preservingTriangles +
                            input.gaussImage->reversingTriangles +
                            input.gaussImage->collapsedTriangles) +
             " triangles, " + std::to_string(input.gaussImage->reversingTriangles) +
             " have a saddle-shaped (orientation-reversing) Gauss image and " +
             std::to_string(input.gaussImage->preservingTriangles) +
             " a convex one, so its Gauss map is not injective. ";
    }
    why += checked.document.patch
               ? "A patch has a support function only where its Gauss map is injective (all "
                 "convex or all saddle-shaped, no fold)"
               : "A closed surface has a support function only if it is convex (its Gauss map "
                 "is then injective)";
    why +=
        "; pass --patches to split it into patches of one curvature sign, each fitted over its "
        "own Gauss image, or offset it with --method levelset";
    if (!allowSingular) throw InputError(why + ", or pass --allow-singular to keep this result");
    checked.warnings.push_back(why + " (kept: --allow-singular)");
  }
  return checked;
}

nlohmann::json supportJson(const CheckedSupport& support) {
  const SupportFunction& h = support.document.function;
  const SupportValidity& v = support.validity;
  nlohmann::json report;
  report["degree"] = h.degree();
  report["coefficients"] = h.coefficients().size();
  report["basis"] = "real_spherical_harmonics";
  report["domain"] = support.document.patch ? "patch" : "sphere";
  if (support.document.patch) {
    report["domain_normals"] = support.document.patch->normals.size();
    report["domain_triangles"] = support.document.patch->triangles.size();
  }
  if (support.document.fit) {
    const SupportFitRecord& fit = *support.document.fit;
    report["fit"] = {{"source", fit.source},
                     {"samples", fit.samples},
                     {"regularization", fit.regularization},
                     {"rms_residual", fit.rmsResidual},
                     {"max_residual", fit.maxResidual}};
    if (support.fit) {
      report["fit"]["size"] = support.fit->size;
      report["fit"]["relative_max_residual"] =
          support.fit->size > 0 ? support.fit->maxResidual / support.fit->size : 0.0;
      report["fit"]["reciprocal_condition"] = support.fit->reciprocalCondition;
      report["fit"]["renormalised_normals"] = support.fit->renormalisedNormals;
    }
  }
  report["regular"] = v.regular();
  report["signs"] = v.regular() ? radiusSignsName(v.signs) : "mixed";
  report["radii"] = {{"min", v.minRadius}, {"max", v.maxRadius}};
  report["normals_checked"] = v.normalsChecked;
  report["sign_counts"] = {{"convex", v.convexNormals},
                           {"saddle", v.saddleNormals},
                           {"concave", v.concaveNormals},
                           {"parabolic", v.parabolicNormals}};
  report["parabolic_crossings"] = v.parabolicCrossings;
  nlohmann::json points = nlohmann::json::array();
  for (std::size_t i = 0; i < v.parabolicPoints.size() && i < 100; ++i) {
    const Eigen::Vector3d& n = v.parabolicPoints[i];
    points.push_back({n.x(), n.y(), n.z()});
  }
  report["parabolic_points"] = points;  // the first 100
  if (v.regular()) {
    report["safe_offset"] = {{"min", finiteOrNull(v.safeOffsetMin)},
                             {"max", finiteOrNull(v.safeOffsetMax)}};
  } else {
    report["safe_offset"] = nullptr;
  }
  if (!support.document.patch) {
    const SupportMeasures measures = supportMeasures(h);
    report["area"] = measures.area;
    report["volume"] = measures.volume;
    report["mean_curvature_integral"] = measures.meanCurvatureIntegral;
    const Eigen::Vector3d steiner = h.linearPart();
    report["steiner_point"] = {steiner.x(), steiner.y(), steiner.z()};
  }
  return report;
}

bool isSupportFunctionFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const nlohmann::json json = nlohmann::json::parse(in, nullptr, false);
  return json.is_object() && json.contains("type") && json["type"].is_string() &&
         json["type"].get<std::string>() == kSupportFunctionJsonType;
}

nlohmann::json supportFileReport(const std::string& path) {
  CheckedSupport checked;
  checked.document = readSupportFunctionJson(path);
  checked.validity =
      analyzeSupportValidity(checked.document.function, validityDomain(checked.document));
  nlohmann::json report = supportJson(checked);
  report["file"] = path;
  report["kind"] = kSupportFunctionJsonType;
  return report;
}

PatchedSupport fitPatches(const std::string& path, const GlobalOptions& options, int degree,
                          double regularization, double parabolicRatio) {
  if (isSupportFunctionFile(path)) {
    throw InputError("'" + path +
                     "' is a support-function file; --patches splits a mesh or a level set");
  }
  LoadOptions load;
  load.purpose = "the input of --patches (a mesh with triangles or a level set)";
  load.progress = makeProgressPrinter(options);
  LoadedInput loaded = loadInput(path, {InputKind::Mesh, InputKind::LevelSet}, load);
  PatchedSupport patched;
  TriangleMesh mesh;
  if (loaded.kind() == InputKind::LevelSet) {
    const openvdb::FloatGrid::Ptr grid = std::move(loaded).take<LevelSetInput>().floatGrid();
    IsoSurfaceOptions iso;
    iso.computeNormals = true;
    mesh = extractIsoSurface(*grid, iso, makeProgressPrinter(options));
    patched.kind = "level set";
    if (mesh.triangles.empty()) {
      throw InputError("'" + path + "' has no zero crossing: its iso-surface is empty");
    }
  } else {
    mesh = std::move(loaded).take<MeshInput>().mesh;
    patched.kind = "mesh";
    if (mesh.triangles.empty()) {
      throw InputError("'" + path +
                       "' has no triangles: splitting into patches needs the surface's "
                       "connectivity (a mesh or a level set), not a point set");
    }
    if (!mesh.hasNormals()) {
      patched.warnings.push_back("'" + path +
                                 "' has no vertex normals: using area-weighted normals of its "
                                 "triangles, which limit the curvature signs and the fits' "
                                 "accuracy to the facets' size");
    }
  }
  SupportPatchOptions patchOptions;
  patchOptions.degree = degree;
  if (regularization >= 0.0) patchOptions.regularization = regularization;
  if (parabolicRatio >= 0.0) patchOptions.parabolicRatio = parabolicRatio;
  status(options,
         "splitting " + path + " (" + patched.kind + ", " + std::to_string(mesh.triangles.size()) +
             " triangles) into patches of one curvature sign, degree " + std::to_string(degree));
  patched.set = fitSupportPatches(mesh, patchOptions, "'" + path + "'");
  if (patched.set.patches.empty()) {
    throw InputError(
        "'" + path + "': no region of one curvature sign could be fitted (" +
        std::to_string(patched.set.smallRegionTriangles) + " triangles in regions too small, " +
        std::to_string(patched.set.rejectedTriangles) + " in regions whose fit failed, " +
        std::to_string(patched.set.parabolicTriangles) + " near-parabolic)");
  }
  const double uncovered = static_cast<double>(patched.set.uncoveredTriangles()) /
                           static_cast<double>(patched.set.triangles);
  if (uncovered > 0.0) {
    patched.warnings.push_back(
        formatNumber(100.0 * uncovered, 3) + "% of the triangles are in no patch (" +
        std::to_string(patched.set.parabolicTriangles) + " near parabolic curves, " +
        std::to_string(patched.set.smallRegionTriangles) + " in regions too small to fit, " +
        std::to_string(patched.set.rejectedTriangles) +
        " in regions whose fit failed): the patches' offsets leave gaps there");
  }
  return patched;
}

void addParabolicRatioOption(CLI::App* command, double& ratio) {
  command
      ->add_option("--parabolic-ratio", ratio,
                   "--patches: leave out the band where the smaller principal curvature is below "
                   "this fraction of the larger (default 0.1; larger: less coverage, more "
                   "accurate patches)")
      ->check(CLI::Range(0.0, 0.99));
}

nlohmann::json patchesJson(const PatchedSupport& patched) {
  const SupportPatchSet& set = patched.set;
  nlohmann::json patches = nlohmann::json::array();
  for (std::size_t i = 0; i < set.patches.size(); ++i) {
    const SupportPatch& p = set.patches[i];
    patches.push_back({{"index", i},
                       {"signs", radiusSignsName(p.signs)},
                       {"triangles", p.triangles.size()},
                       {"samples", p.fit.samples},
                       {"degree", p.fit.degree},
                       {"rms_residual", p.fit.rmsResidual},
                       {"max_residual", p.fit.maxResidual},
                       {"radii", {{"min", p.validity.minRadius}, {"max", p.validity.maxRadius}}},
                       {"safe_offset",
                        {{"min", finiteOrNull(p.validity.safeOffsetMin)},
                         {"max", finiteOrNull(p.validity.safeOffsetMax)}}}});
  }
  nlohmann::json report;
  report["input_kind"] = patched.kind;
  report["domain"] = "patches";
  report["patches"] = patches;
  report["triangles"] = {{"total", set.triangles},
                         {"convex", set.convexTriangles},
                         {"saddle", set.saddleTriangles},
                         {"concave", set.concaveTriangles},
                         {"parabolic", set.parabolicTriangles},
                         {"small_regions", set.smallRegionTriangles},
                         {"rejected", set.rejectedTriangles},
                         {"uncovered", set.uncoveredTriangles()}};
  report["safe_offset"] = {{"min", finiteOrNull(set.safeOffsetMin())},
                           {"max", finiteOrNull(set.safeOffsetMax())}};
  return report;
}

std::string patchesText(const nlohmann::json& report, const std::string& indent) {
  const auto side = [](const nlohmann::json& value, const char* infinite) {
    return value.is_null() ? std::string(infinite) : formatNumber(value.get<double>(), 6);
  };
  const auto& t = report["triangles"];
  std::string text = indent + std::to_string(report["patches"].size()) +
                     " patches of one curvature sign, " + "each fitted over its Gauss image; of " +
                     t["total"].dump() + " triangles: " + t["convex"].dump() + " convex, " +
                     t["saddle"].dump() + " saddle, " + t["concave"].dump() + " concave, " +
                     t["parabolic"].dump() + " near-parabolic; " + t["uncovered"].dump() +
                     " in no patch\n";
  for (const auto& p : report["patches"]) {
    text += indent + "  patch " + p["index"].dump() + ": " + p["signs"].get<std::string>() + ", " +
            p["triangles"].dump() + " triangles, degree " + p["degree"].dump() + ", residual max " +
            formatNumber(p["max_residual"].get<double>(), 3) + ", safe offsets (" +
            side(p["safe_offset"]["min"], "-inf") + ", " + side(p["safe_offset"]["max"], "inf") +
            ")";
    if (p.contains("output")) text += " -> " + p["output"].get<std::string>();
    text += "\n";
  }
  text += indent + "safe offsets for all patches: (" + side(report["safe_offset"]["min"], "-inf") +
          ", " + side(report["safe_offset"]["max"], "inf") + ")\n";
  return text;
}

void requireRegularPatchOffset(const PatchedSupport& patched, double distance, bool allowSingular,
                               std::vector<std::string>& warnings) {
  const double lo = patched.set.safeOffsetMin();
  const double hi = patched.set.safeOffsetMax();
  if (distance > lo && distance < hi) return;
  const std::string message =
      "offset " + formatNumber(distance, 6) + " is outside the range (" + formatNumber(lo, 6) +
      ", " + formatNumber(hi, 6) +
      ") where every patch stays regular (a principal radius r + d would change sign: cusps or "
      "self-intersections)";
  if (!allowSingular) {
    throw InputError(message + "; choose a distance inside it or pass --allow-singular");
  }
  warnings.push_back(message + " (kept: --allow-singular)");
}

std::string supportText(const nlohmann::json& report, const std::string& indent) {
  std::string text;
  text += indent + "support function: degree " + report["degree"].dump() + " (" +
          report["coefficients"].dump() + " coefficients), domain " +
          report["domain"].get<std::string>() + "\n";
  if (report.contains("fit")) {
    const auto& fit = report["fit"];
    text += indent + "fit: " + fit["samples"].dump() + " samples, residual rms " +
            formatNumber(fit["rms_residual"].get<double>(), 6) + ", max " +
            formatNumber(fit["max_residual"].get<double>(), 6);
    if (fit.contains("relative_max_residual")) {
      text += " (" + formatNumber(fit["relative_max_residual"].get<double>(), 6) + " of the size)";
    }
    text += ", regularisation " + formatNumber(fit["regularization"].get<double>(), 6) + "\n";
  }
  text += indent + (report["regular"].get<bool>() ? "regular, " : "SINGULAR, ") +
          report["signs"].get<std::string>() + ": principal radii " +
          formatNumber(report["radii"]["min"].get<double>(), 6) + " .. " +
          formatNumber(report["radii"]["max"].get<double>(), 6) + " on " +
          report["normals_checked"].dump() + " normals";
  if (report["parabolic_crossings"].get<std::size_t>() > 0) {
    text += ", " + report["parabolic_crossings"].dump() + " parabolic crossings";
  }
  text += "\n";
  if (!report["safe_offset"].is_null()) {
    const auto side = [](const nlohmann::json& value, const char* infinite) {
      return value.is_null() ? std::string(infinite) : formatNumber(value.get<double>(), 6);
    };
    text += indent + "safe offsets: (" + side(report["safe_offset"]["min"], "-inf") + ", " +
            side(report["safe_offset"]["max"], "inf") + ")\n";
  }
  if (report.contains("volume")) {
    text += indent + "volume " + formatNumber(report["volume"].get<double>(), 6) + ", area " +
            formatNumber(report["area"].get<double>(), 6) + "\n";
  }
  return text;
}

}  // namespace d2vdb::cli
