// Shared plumbing of the d2vdb command: global options, exit codes, progress and report output.
#pragma once

#include <openvdb/openvdb.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "d2vdb/core/Progress.h"

namespace d2vdb::cli {

/// Process exit codes, as documented in the README.
enum ExitCode : int {
  kSuccess = 0,
  kUsageError = 1,  ///< bad command line
  kBadInput = 2,    ///< input file or parameter rejected (d2vdb::InputError)
  kRunFailure = 3,  ///< failure while running (d2vdb::RuntimeFailure, I/O, out of memory)
};

/// Options every sub-command accepts.
struct GlobalOptions {
  int threads = 0;     ///< 0 = all cores
  bool quiet = false;  ///< no progress or summaries on stderr
  bool json = false;   ///< one JSON document on stdout instead of text (reporting sub-commands)
};

/// A sub-command's body: runs after parsing, returns an exit code, may throw d2vdb exceptions.
using CommandBody = std::function<int()>;

/// Registers one sub-command on `app`; `body` is stored and run when the sub-command was chosen.
/// Each sub-command lives in its own .cc and exposes one `add...Command` function.
struct CommandRegistry {
  std::vector<std::pair<CLI::App*, CommandBody>> commands;
  void add(CLI::App* subcommand, CommandBody body) {
    commands.emplace_back(subcommand, std::move(body));
  }
};

/// Prints a status line to stderr unless --quiet.
void status(const GlobalOptions& options, std::string_view message);

/// Prints a warning to stderr (even with --quiet: warnings are not progress).
void warning(std::string_view message);

/// A ProgressCallback that draws a progress line on stderr once an operation has run for more than
/// a second (and never with --quiet). Stage changes start a new line.
ProgressCallback makeProgressPrinter(const GlobalOptions& options);

/// Wall-clock stopwatch in seconds.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

/// Writes `report` to stdout as one pretty-printed JSON document; bytes of its strings that are
/// not valid UTF-8 are written as U+FFFD.
void printJson(const nlohmann::json& report);

/// Throws InputError when the level set `grid` of a shape whose longest side is `longestSide`
/// (world units) has no active voxel, so that a voxel size far beyond the shape never writes an
/// empty file; warns when the shape spans fewer than four voxels. `what` names the shape.
void checkResolvesShape(const openvdb::FloatGrid& grid, double longestSide,
                        const std::string& what);

/// Validators for numeric options that must be finite and positive (or at least zero). Unlike
/// CLI::PositiveNumber they do not quote the double range in their message: "--resolution: must
/// be a positive number, got 0".
CLI::Validator positiveNumber();
CLI::Validator nonNegativeNumber();

/// Adds an option that reads exactly three comma- or space-separated numbers (e.g. "1,2,3").
CLI::Option* addVector3Option(CLI::App& app, const std::string& name, std::array<double, 3>& value,
                              const std::string& description);

// One registration function per sub-command (tools/cli/<Name>Command.cc).
void addInfoCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addMesh2SdfCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addPrimitiveCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addConvertCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addMeshCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addSliceCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addProjectCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addHausdorffCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addFitCurveCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addFitSurfaceCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addFieldCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addQueryCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addSmoothCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addSupportCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);
void addOffsetCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options);

}  // namespace d2vdb::cli
