// What the fit commands share (`d2vdb fit-curve`, `d2vdb fit-surface`): the command-line options
// of FitOptions every fitter takes, and the JSON and text reports of a fit. The JSON keys are the
// documented, stable output format (README, "JSON output").
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <initializer_list>
#include <string>

#include "Command.h"
#include "d2vdb/fit/FitHistory.h"
#include "d2vdb/fit/FitMethod.h"
#include "d2vdb/fit/FitOptions.h"

namespace d2vdb::cli {

/// The help texts that differ between the fit commands.
struct FitOptionHelp {
  std::string spline;      ///< what is fitted: "curve", "surface"
  std::string smoothness;  ///< --smoothness: the bending energy and its automatic default
  std::string stretch;     ///< --stretch: the stretching energy
  std::string plainSdm;    ///< --plain-sdm: what the exact second-order terms are left out of
};

/// Declares the options of `fit` that every fit command takes: --iterations, --smoothness,
/// --smoothing-bias, --step-smoothness, --stretch, --pdm-weight, --tolerance, --step-tolerance,
/// --move-tolerance, and --plain-sdm (sets `plainSdm`; see applyPlainSdm()). Each number is
/// checked as it is parsed (a non-negative or positive finite number, an iteration cap in
/// [0, 10^6]); the defaults are those of `fit` at registration.
void declareFitOptions(CLI::App& command, FitOptions& fit, bool& plainSdm,
                       const FitOptionHelp& help);

/// Throws InputError (before any work) when --init is neither one of `shapes` (the generated
/// initial splines, e.g. plane, cylinder, torus) nor an existing file, saying both: "--init
/// 'sphere' is not plane, cylinder or torus, and there is no file of that name". `file` names what
/// a file must hold ("a surface .json").
void checkInitOption(const std::string& init, std::initializer_list<const char*> shapes,
                     const std::string& file);

/// {"method", "status", "reason", "iterations", "rms_distance", "max_distance", "smoothness" (of
///  the last iteration), "history": [{"iteration", "objective", "rms_distance", "max_distance",
///  "step_length", "step_scale", "damping", "target_move", "smoothness",
///  "second_order_weight"}]}
nlohmann::json fitReportJson(const FitReport& report, FitMethod method);

/// "<method> fit: <status> after N iterations (<reason>)" and the history as a table, one row per
/// iteration, each line ending in '\n'.
std::string fitReportText(const FitReport& report, FitMethod method);

/// The report of a fit that wrote its result to `out`: `json` with "seconds", `text` as the
/// answer (stdout), and "wrote OUT" on stderr now, unless --json.
Report fitAnswer(nlohmann::json json, std::string text, double seconds, const std::string& out,
                 const CommandContext& context);

}  // namespace d2vdb::cli
