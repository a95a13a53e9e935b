// What the fit commands share (FitReports.h).
#include "FitReports.h"

#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "Command.h"
#include "d2vdb/core/Error.h"

namespace d2vdb::cli {

void checkInitOption(const std::string& init, std::initializer_list<const char*> shapes,
                     const std::string& file) {
  const std::vector<std::string> names(shapes.begin(), shapes.end());
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == init) return;
    list += (i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ")) + names[i];
  }
  std::error_code ec;
  if (std::filesystem::exists(init, ec)) return;  // a file: loading it says what it holds
  throw InputError("--init '" + init + "' is not " + list +
                   ", and there is no file of that name (" + file + " was expected)");
}

void declareFitOptions(CLI::App& command, FitOptions& fit, bool& plainSdm,
                       const FitOptionHelp& help) {
  command.add_option("--iterations", fit.maxIterations, "Iteration cap")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  command.add_option("--smoothness", fit.smoothness, help.smoothness)->check(nonNegativeNumber());
  command
      .add_option("--smoothing-bias", fit.automaticSmoothingBias,
                  "Automatic smoothness: its shift of the fit as a fraction of the fit's "
                  "resolution RMS x sqrt(control points / terms)")
      ->capture_default_str()
      ->check(positiveNumber());
  command
      .add_option("--step-smoothness", fit.stepSmoothness,
                  "Damping of rough and tangential control-point moves (relative; no bias)")
      ->capture_default_str()
      ->check(nonNegativeNumber());
  command.add_option("--stretch", fit.stretch, help.stretch)
      ->capture_default_str()
      ->check(nonNegativeNumber());
  command.add_option("--pdm-weight", fit.pdmWeight, "PDM weight of tdm+pdm")
      ->capture_default_str()
      ->check(nonNegativeNumber());
  command
      .add_option("--tolerance", fit.distanceTolerance,
                  "Stop when the RMS distance reaches this (world units; 0 = off)")
      ->capture_default_str()
      ->check(nonNegativeNumber());
  command
      .add_option(
          "--step-tolerance", fit.stepTolerance,
          "Converged when the " + help.spline + " moves by less than this fraction of its size")
      ->capture_default_str()
      ->check(nonNegativeNumber());
  command
      .add_option("--move-tolerance", fit.moveTolerance,
                  "Converged when the " + help.spline +
                      "'s move across the target and its RMS change, extrapolated at their "
                      "rate of convergence, are below this fraction of the fit's precision")
      ->capture_default_str()
      ->check(nonNegativeNumber());
  command.add_flag("--plain-sdm", plainSdm, help.plainSdm);
}

nlohmann::json fitReportJson(const FitReport& report, FitMethod method) {
  nlohmann::json rows = nlohmann::json::array();
  for (const FitIteration& row : report.history) {
    rows.push_back({{"iteration", row.iteration},
                    {"objective", row.objective},
                    {"rms_distance", row.rmsDistance},
                    {"max_distance", row.maxDistance},
                    {"step_length", row.stepLength},
                    {"step_scale", row.stepScale},
                    {"damping", row.damping},
                    {"target_move", row.targetMove},
                    {"smoothness", row.smoothness},
                    {"second_order_weight", row.secondOrderWeight}});
  }
  return {{"method", fitMethodName(method)},
          {"status", fitStatusName(report.status)},
          {"reason", report.reason},
          {"iterations", report.iterations()},
          {"rms_distance", report.history.back().rmsDistance},
          {"max_distance", report.history.back().maxDistance},
          {"smoothness", report.history.back().smoothness},
          {"history", rows}};
}

namespace {

// printf into a std::string.
template <typename... Values>
std::string format(const char* pattern, Values... values) {
  const int length = std::snprintf(nullptr, 0, pattern, values...);
  std::string text(static_cast<std::size_t>(length) + 1, '\0');
  std::snprintf(text.data(), text.size(), pattern, values...);
  text.pop_back();
  return text;
}

}  // namespace

std::string fitReportText(const FitReport& report, FitMethod method) {
  std::string text =
      format("%s fit: %s after %d iterations (%s)\n", fitMethodName(method),
             fitStatusName(report.status), report.iterations(), report.reason.c_str());
  text += format("%5s %14s %12s %12s %12s %12s %7s %9s %9s %6s\n", "iter", "objective", "rms",
                 "max", "step", "move", "scale", "damping", "smooth", "newton");
  for (const FitIteration& row : report.history) {
    text +=
        format("%5d %14.6e %12.5e %12.5e %12.5e %12.5e %7.4f %9.2e %9.2e %6.3f\n", row.iteration,
               row.objective, row.rmsDistance, row.maxDistance, row.stepLength, row.targetMove,
               row.stepScale, row.damping, row.smoothness, row.secondOrderWeight);
  }
  return text;
}

Report fitAnswer(nlohmann::json json, std::string text, double seconds, const std::string& out,
                 const CommandContext& context) {
  Report report;
  report.json = std::move(json);
  report.json["seconds"] = seconds;
  report.text = std::move(text);
  report.textKind = Report::Text::Answer;
  if (!context.options().json) context.status("wrote " + out);
  return report;
}

}  // namespace d2vdb::cli
