// d2vdb support: fit a support function (real spherical harmonics up to a degree) to a mesh, a
// point set with normals, a level set or a field, check where it is regular, and write it as a
// support-function .json file (io/SupportFunctionJson.h).
#include <filesystem>
#include <string>
#include <vector>

#include "Command.h"
#include "ReportText.h"
#include "SupportReports.h"
#include "d2vdb/core/AtomicFileSet.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/io/SupportFunctionJson.h"
#include "d2vdb/io/SupportInput.h"

namespace d2vdb::cli {
namespace {

struct SupportArguments {
  std::string input, output;
  int degree = 16;
  double regularization = -1.0;
  bool allowSingular = false;
  bool patches = false;
  double parabolicRatio = -1.0;
};

void declareSupport(CLI::App& command, SupportArguments& args) {
  command.add_option("input", args.input, "Mesh, point set (.ply), level set or field (.vdb)")
      ->required();
  command.add_option("--out", args.output, "Output support-function .json (written atomically)")
      ->required();
  command
      .add_option("--degree", args.degree,
                  "Spherical-harmonic degree L: (L + 1)^2 coefficients, at most " +
                      std::to_string(kMaxSupportDegree))
      ->capture_default_str();
  command
      .add_option("--regularization", args.regularization,
                  "Smoothness weight lambda >= 0 (default 1e-10 over the sphere, 1e-13 over a "
                  "patch's Gauss image; see the README)")
      ->check(CLI::Range(0.0, 1e6));
  command.add_flag("--allow-singular", args.allowSingular,
                   "Keep a support function that is singular on its domain (warning instead of "
                   "refusal)");
  command.add_flag("--patches", args.patches,
                   "Split a non-convex mesh or level set into patches of one curvature sign and "
                   "fit each over its Gauss image (one .json per patch)");
  addParabolicRatioOption(command, args.parabolicRatio);
}

// OUT's stem + "_p<index>" + extension: the file of one patch.
std::filesystem::path patchOutput(const std::filesystem::path& output, std::size_t index) {
  std::filesystem::path name = output;
  name.replace_filename(output.stem().string() + "_p" + std::to_string(index) +
                        output.extension().string());
  return name;
}

// `support --patches`: fit the patches, write each as its own support-function file over its
// Gauss image (all computed before any is written), report them.
Report runPatches(const SupportArguments& args, const CommandContext& context,
                  const Stopwatch& clock) {
  const PatchedSupport patched =
      loadAndFitPatches(args.input, args.degree, args.regularization, args.parabolicRatio, context);
  for (const std::string& message : patched.warnings) warning(message);
  Report report;
  report.json = patchesJson(patched);
  const std::vector<SupportFunctionDocument> documents =
      supportPatchDocuments(patched.set, args.input);
  // Every patch file to a temporary name; none replaces its target unless all were written.
  AtomicFileSet files;
  for (std::size_t i = 0; i < documents.size(); ++i) {
    const std::string path = patchOutput(args.output, i).string();
    files.stage(path, [&](const std::filesystem::path& temporary) {
      writeSupportFunctionJson(temporary, documents[i]);
    });
    report.json["patches"][i]["output"] = path;
  }
  files.commit();
  report.json["input"] = args.input;
  report.json["warnings"] = patched.warnings;
  report.json["seconds"] = clock.seconds();
  report.text = "wrote " + std::to_string(documents.size()) + " patch files (" +
                inputKindName(patched.kind) + " " + args.input + ", " +
                std::to_string(clock.seconds()) + " s):\n" + patchesText(report.json, "  ");
  return report;
}

Report runSupport(const SupportArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  if (args.patches) return runPatches(args, context, clock);
  const SupportInput input = loadSupportInput(args.input, context.progress());
  if (input.document) {
    throw InputError("'" + args.input +
                     "' already is a support function; 'd2vdb support' fits one to a mesh, "
                     "point set, level set or field");
  }
  for (const std::string& message : input.warnings) warning(message);
  const char* const kind = supportInputKindName(input.kind);
  context.status("fitting degree " + std::to_string(args.degree) + " to " +
                 std::to_string(input.samples.points.size()) + " samples of " + args.input + " (" +
                 kind + ")");
  const CheckedSupport support =
      fitAndCheck(input, args.input, {args.degree, args.regularization, args.allowSingular});
  for (const std::string& message : support.warnings) warning(message);
  writeSupportFunctionJson(args.output, support.document);

  Report report;
  report.json = supportJson(support);
  if (input.gaussImage) {
    report.json["gauss_image"] = {{"preserving_triangles", input.gaussImage->preservingTriangles},
                                  {"reversing_triangles", input.gaussImage->reversingTriangles},
                                  {"collapsed_triangles", input.gaussImage->collapsedTriangles}};
  }
  std::vector<std::string> warnings = input.warnings;
  warnings.insert(warnings.end(), support.warnings.begin(), support.warnings.end());
  const std::string wrote =
      addFileToFileKeys(report.json, {args.input, kind, args.output, clock.seconds(), warnings});
  report.text = wrote + "\n" + supportText(report.json, "  ");
  return report;
}

// --out (with --patches the directory and extension of every patch's file).
std::vector<OutputFile> outputsOfSupport(const SupportArguments& args) {
  return {{"--out", args.output, OutputFormat::Json}};
}

}  // namespace

void addSupportCommand(CommandRegistry& registry) {
  registry.add<SupportArguments>(
      {"support",
       "Fit a support function h(n) = x . n (real spherical harmonics up to --degree) to a\n"
       "closed convex surface, or to a patch whose Gauss map is injective (an open mesh is\n"
       "fitted over its own Gauss image), by least squares on the oriented samples (X_i, n_i):\n"
       "sum |X_i - x_h(n_i)|^2 with x_h(n) = h(n) n + grad_S h(n). Reports the residuals, the\n"
       "principal radii, the parabolic set and the safe offset range, and writes the function\n"
       "as .json. Inputs: meshes (.obj, .ply, .stl; vertex normals, or area-weighted ones),\n"
       "point sets with normals (.ply with nx ny nz), level sets and fields (.vdb; band\n"
       "footpoints and normals). A non-convex closed surface has no support function: the fit\n"
       "is singular and refused (exit 2) unless --allow-singular; with --patches a mesh or level\n"
       "set is split into connected regions of one curvature sign (convex, saddle, concave;\n"
       "a band along the parabolic curves is left out), each fitted over its own Gauss image\n"
       "and written to OUT's name with _p<k> before .json.\n"
       "Example: d2vdb support volumes/ellipsoid.ply --degree 8 --out ellipsoid-sf.json\n"
       "         d2vdb support volumes/torus.vdb --patches --out torus-sf.json",
       "use a lower --degree, or an input with fewer samples (a coarser mesh or level set)",
       declareSupport, runSupport, outputsOfSupport});
}

}  // namespace d2vdb::cli
