// Shared by the support and offset sub-commands: loading oriented samples from any input
// (meshes, point sets with normals, level sets and fields), fitting and checking a support
// function, and reporting on it.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "Command.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/io/SupportFunctionJson.h"
#include "d2vdb/support/SupportFit.h"
#include "d2vdb/support/SupportPatches.h"
#include "d2vdb/support/SupportSamples.h"
#include "d2vdb/support/SupportValidity.h"

namespace d2vdb::cli {

/// What an input file gives a support function.
struct SupportInput {
  /// "mesh" (closed), "mesh patch" (open mesh: fitted over its Gauss image), "points", "level set",
  /// "field" or "support function" (a .json written by `d2vdb support`).
  std::string kind;
  OrientedSamples samples;                          ///< empty for a support-function file
  std::optional<SphericalTriangulation> patch;      ///< the Gauss image of an open mesh
  std::optional<MeshGaussImage> gaussImage;         ///< meshes: how the Gauss map orients triangles
  std::optional<SupportFunctionDocument> document;  ///< a support-function file
  std::vector<std::string> warnings;
};

/// Loads `path` through loadInput() (recognised by content): meshes (vertices with their
/// normals, or area-weighted ones), .ply point sets with nx ny nz, .vdb level sets and field
/// files (samplesFromField()), and support-function .json files (isSupportFunctionFile()).
/// Throws InputError for anything else or a malformed file.
SupportInput loadSupportInput(const std::string& path, const GlobalOptions& options);

/// The band footpoints and normals of a surface's approximant field: one sample per active voxel
/// within half a voxel of the zero level (voxels flagged at the cut locus skipped), in the grid's
/// deterministic iteration order. Throws InputError (naming `source`) for a field of a curve or
/// points, or one without such voxels.
OrientedSamples samplesFromField(const ApproximantField& field, const std::string& source);

/// A fitted (or loaded) support function with its checks.
struct CheckedSupport {
  SupportFunctionDocument document;
  std::optional<SupportFitReport> fit;  ///< when fitted here
  SupportValidity validity;
  std::vector<std::string> warnings;
};

/// A fit whose max residual exceeds this fraction of the samples' bounding-box diagonal is
/// refused like a singular one: the input is not one support-function surface.
inline constexpr double kMaxRelativeSupportResidual = 0.02;

/// Fits `input` at `degree` (regularisation < 0: the default of its domain, sphere or patch), or
/// takes its support-function document, and analyses the validity over its domain. Unless
/// `allowSingular`, throws InputError when the function is singular there (not convex, or a patch
/// whose Gauss map is not injective) or a fit misses its samples by more than
/// kMaxRelativeSupportResidual of their size, explaining why and what to do; with
/// `allowSingular` that becomes a warning.
CheckedSupport fitAndCheck(const SupportInput& input, const std::string& source, int degree,
                           double regularization, bool allowSingular);

/// The validity domain of a document: its patch, or validationSphere(degree).
SphericalTriangulation validityDomain(const SupportFunctionDocument& document);

/// The report keys shared by `support`, `offset` and `info` (README, "JSON output").
nlohmann::json supportJson(const CheckedSupport& support);

/// Whether `path` holds a JSON object whose "type" is "support_function" (false for anything
/// else, invalid JSON included: the reader chosen then reports the problem).
bool isSupportFunctionFile(const std::string& path);

/// `d2vdb info` on a support-function file: {"file", "kind": "support_function"} plus
/// supportJson() of the function and its validity over its domain.
nlohmann::json supportFileReport(const std::string& path);

/// The patches of a non-convex surface (`--patches`), with where they came from.
struct PatchedSupport {
  std::string kind;  ///< "mesh" or "level set" (its zero iso-surface, marching cubes)
  SupportPatchSet set;
  std::vector<std::string> warnings;
};

/// Loads `path` as a mesh with triangles, or a level set (.vdb) whose zero iso-surface is
/// extracted (marching cubes, gradient normals), and fits support-function patches of one
/// curvature sign to it (fitSupportPatches at `degree`; regularisation < 0: the patch default;
/// parabolicRatio < 0: SupportPatchOptions' default).
/// Throws InputError for point sets and support-function files (the split needs the surface's
/// connectivity), malformed files, or when no region could be fitted.
PatchedSupport fitPatches(const std::string& path, const GlobalOptions& options, int degree,
                          double regularization, double parabolicRatio);

/// Adds `--parabolic-ratio` (for --patches) to `command`, stored in `ratio` (default -1: unset).
void addParabolicRatioOption(CLI::App* command, double& ratio);

/// The report of fitPatches(): "patches" (per patch: signs, triangles, samples, degree, fit
/// residuals, radii, safe offsets, output when written), triangle counts by curvature class, what
/// is uncovered and the safe offset range common to all patches.
nlohmann::json patchesJson(const PatchedSupport& patched);

/// A few indented lines for the text output of patchesJson().
std::string patchesText(const nlohmann::json& report, const std::string& indent);

/// Throws InputError unless every patch is regular at `distance` (inside the common safe range);
/// with `allowSingular` adds a warning instead.
void requireRegularPatchOffset(const PatchedSupport& patched, double distance, bool allowSingular,
                               std::vector<std::string>& warnings);

/// A few indented lines for the text output.
std::string supportText(const nlohmann::json& report, const std::string& indent);

}  // namespace d2vdb::cli
