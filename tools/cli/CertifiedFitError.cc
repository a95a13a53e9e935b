#include "CertifiedFitError.h"

#include <sstream>

#include "JsonReports.h"
#include "ReportText.h"
#include "d2vdb/core/Error.h"

namespace d2vdb::cli {

void declareCertifyOption(CLI::App& command, double& tolerance) {
  command
      .add_option("--certify", tolerance,
                  "Also bound the fit's largest error h(fit -> target) by a certified bracket "
                  "this wide, relative to the diagonal of both shapes' boxes (e.g. 1e-4; 0: "
                  "none). Targets: level sets and fields (their marching-cubes mesh), meshes, "
                  "points, B-spline curves and surfaces")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.1));
}

std::optional<HausdorffInput> certifyTarget(const std::string& target, double tolerance,
                                            double offset, const CommandContext& context) {
  if (tolerance == 0.0) return std::nullopt;
  if (offset != 0.0) {
    throw InputError("--certify measures the fit against its target, not an offset of it");
  }
  LoadOptions load;
  load.purpose = "a target that --certify compares with";
  try {
    return loadHausdorffInput(target, load, context.progress());
  } catch (const InputError& error) {
    throw InputError(std::string("--certify: ") + error.what());
  }
}

nlohmann::json certifiedFitError(HausdorffInput fit, const HausdorffInput& target, double tolerance,
                                 const CommandContext& context, std::string& text) {
  const Stopwatch clock;
  HausdorffRequest request;
  request.tolerance = tolerance;
  request.relative = true;
  request.oneSided = true;
  request.progress = context.progress();
  const HausdorffComparison comparison = compareHausdorff(fit, target, request);
  const DirectedHausdorffBracket& bracket = comparison.result.aToB;
  std::ostringstream line;
  line.precision(6);
  line << "certified largest error h(fit -> target) in [" << bracket.lower << ", " << bracket.upper
       << "] (target as " << comparison.b.description << ")\n";
  text = line.str();
  if (!bracket.warning.empty()) warning(bracket.warning);
  return {{"lower_bound", bracket.lower},
          {"upper_bound", bracket.upper},
          {"tolerance", comparison.tolerance},
          {"target_as", comparison.b.description},
          {"from_point", pointJson(bracket.witness)},
          {"to_point", pointJson(bracket.witnessClosest)},
          {"converged", bracket.converged},
          {"seconds", clock.seconds()}};
}

}  // namespace d2vdb::cli
