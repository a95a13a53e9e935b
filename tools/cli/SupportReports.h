// Reports of the support, offset and info sub-commands on support functions (README, "JSON
// output"), and the option they share.
#pragma once

#include <CLI/CLI.hpp>

#include <nlohmann/json.hpp>

#include <string>

#include "Command.h"
#include "d2vdb/io/SupportInput.h"

namespace d2vdb::cli {

/// The report keys shared by `support`, `offset` and `info`: degree, coefficients, basis, domain
/// (with its size for a patch), the fit record, the validity over the domain (regular, signs,
/// radii, sign counts, parabolic crossings and points, safe offsets) and, over the whole sphere,
/// area, volume, mean-curvature integral and Steiner point.
nlohmann::json supportJson(const CheckedSupport& support);

/// A few indented lines for the text output of supportJson().
std::string supportText(const nlohmann::json& report, const std::string& indent);

/// `d2vdb info` on a support-function file `path`: {"file", "kind": "support_function"} plus
/// supportJson() of `support` (analyzeSupportDocument()).
nlohmann::json supportFileReport(const std::string& path, const CheckedSupport& support);

/// The report of fitPatches(): "input_kind", "patches" (per patch: signs, triangles, samples,
/// degree, fit residuals, radii, safe offsets), triangle counts by curvature class, what is
/// uncovered and the safe offset range common to all patches.
nlohmann::json patchesJson(const PatchedSupport& patched);

/// A few indented lines for the text output of patchesJson() (with each patch's "output" when the
/// caller added it).
std::string patchesText(const nlohmann::json& report, const std::string& indent);

/// Adds `--parabolic-ratio` (for --patches) to `command`, stored in `ratio` (default -1: unset).
void addParabolicRatioOption(CLI::App& command, double& ratio);

/// The patch options of --degree, --regularization and --parabolic-ratio (< 0: unset, the
/// default of SupportPatchOptions).
SupportPatchOptions patchOptions(int degree, double regularization, double parabolicRatio);

/// `--patches`: loads `input` (a mesh, or a level set's zero iso-surface), says so in a status
/// line, and fits its patches of one curvature sign (fitPatches() with patchOptions()).
PatchedSupport loadAndFitPatches(const std::string& input, int degree, double regularization,
                                 double parabolicRatio, const CommandContext& context);

}  // namespace d2vdb::cli
