// --certify of the fit commands: the certified Hausdorff bracket of h(fit -> target) beside the
// sampled errors the fitters report (a sampled maximum is only a lower bound).
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "Command.h"
#include "d2vdb/io/HausdorffInput.h"

namespace d2vdb::cli {

/// Declares --certify TOL (relative to the diagonal of the fit's and the target's boxes; 0, the
/// default, for none).
void declareCertifyOption(CLI::App& command, double& tolerance);

/// The fit's target as a Hausdorff input, read before the fit so that a target that cannot be
/// compared (a polyline file, a curve field, an offset fit) is refused first: InputError naming
/// --certify. Empty when `tolerance` is 0.
std::optional<HausdorffInput> certifyTarget(const std::string& target, double tolerance,
                                            double offset, const CommandContext& context);

/// h(fit -> target) to within `tolerance` (relative) as {"lower_bound", "upper_bound",
/// "tolerance" (world units), "target_as", "from_point", "to_point", "converged", "seconds"}, and
/// one line for the text report.
nlohmann::json certifiedFitError(HausdorffInput fit, const HausdorffInput& target, double tolerance,
                                 const CommandContext& context, std::string& text);

}  // namespace d2vdb::cli
