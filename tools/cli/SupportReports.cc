#include "SupportReports.h"

#include <cmath>

#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/support/SupportMeasures.h"

namespace d2vdb::cli {
namespace {

// A number for JSON, with null for +-infinity (JSON has none): an unbounded side of a range.
nlohmann::json finiteOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace

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
      report["fit"]["renormalised_normals"] = support.fit->renormalizedNormals;
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

nlohmann::json supportFileReport(const std::string& path, const CheckedSupport& support) {
  nlohmann::json report = supportJson(support);
  report["file"] = path;
  report["kind"] = kSupportFunctionJsonType;
  return report;
}

void addParabolicRatioOption(CLI::App& command, double& ratio) {
  command
      .add_option("--parabolic-ratio", ratio,
                  "--patches: leave out the band where the smaller principal curvature is below "
                  "this fraction of the larger (default 0.1; larger: less coverage, more "
                  "accurate patches)")
      ->check(CLI::Range(0.0, 0.99));
}

SupportPatchOptions patchOptions(int degree, double regularization, double parabolicRatio) {
  SupportPatchOptions options;
  options.degree = degree;
  if (regularization >= 0.0) options.regularization = regularization;
  if (parabolicRatio >= 0.0) options.parabolicRatio = parabolicRatio;
  return options;
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
  report["input_kind"] = inputKindName(patched.kind);
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

PatchedSupport loadAndFitPatches(const std::string& input, int degree, double regularization,
                                 double parabolicRatio, const CommandContext& context) {
  const PatchSurface surface = loadPatchSurface(input, context.progress());
  context.status("splitting " + input + " (" + inputKindName(surface.kind) + ", " +
                 std::to_string(surface.mesh.triangles.size()) +
                 " triangles) into patches of one curvature sign, degree " +
                 std::to_string(degree));
  return fitPatches(surface, patchOptions(degree, regularization, parabolicRatio), input);
}

}  // namespace d2vdb::cli
