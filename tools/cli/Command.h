// The shape every sub-command of the d2vdb command shares: an arguments struct, a function that
// declares its options, and a function that runs it and returns a Report, registered together
// with the advice given when it runs out of memory. Also the global options, exit codes, progress
// and the option validators.
#pragma once

#include <openvdb/openvdb.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "OutputFiles.h"
#include "d2vdb/core/Progress.h"
#include "d2vdb/core/ResourceBudget.h"

namespace d2vdb::cli {

/// Process exit codes, as documented in the README.
enum ExitCode : int {
  kSuccess = 0,
  kUsageError = 1,  ///< bad command line
  kBadInput = 2,    ///< input file or parameter rejected (d2vdb::InputError)
  kRunFailure = 3,  ///< failure while running (d2vdb::RuntimeFailure, I/O, out of memory)
};

/// Options every sub-command accepts (declared once, on the top-level command).
struct GlobalOptions {
  int threads = 0;     ///< 0 = all cores
  bool quiet = false;  ///< no progress or summaries on stderr
  bool json = false;   ///< the report as one JSON document on stdout instead of text
  /// --max-memory and --max-output: what every command checks its estimates against before it
  /// allocates or writes anything (core/ResourceBudget.h).
  ResourceBudget budget;
};

/// What a sub-command returns: its report, as JSON and as text for people, and its exit code.
struct Report {
  /// Where the text goes: a summary of work done goes to stderr and is silenced by --quiet; the
  /// answer of a command that exists to print it (info, query, project, hausdorff) goes to stdout.
  enum class Text { Summary, Answer };

  nlohmann::json json;  ///< printed on stdout with --json (the documented, stable keys)
  std::string text;     ///< printed without --json; empty prints nothing
  Text textKind = Text::Summary;
  int exitCode = kSuccess;
};

/// Prints `report`: its JSON with --json, otherwise its text (an answer on stdout, a summary on
/// stderr unless --quiet). A summary's text is printed as given; lines end with '\n'.
void printReport(const Report& report, const GlobalOptions& options);

/// A ProgressCallback that shows progress on stderr once the work has run for a second (never with
/// --quiet): one line per stage, its percentage never decreasing; on a terminal the line is
/// redrawn in place at most ten times a second, in a log a stage gets a line when it shows, then
/// at most one every ten seconds, and one at its end.
ProgressCallback makeProgressPrinter(const GlobalOptions& options);

/// What a sub-command's run function may use besides its arguments.
class CommandContext {
 public:
  CommandContext(const GlobalOptions& options, const CLI::App& command)
      : options_(options), command_(command), progress_(makeProgressPrinter(options)) {}

  const GlobalOptions& options() const { return options_; }
  /// How often option `name` (e.g. "--voxel-size") was given on the command line.
  std::size_t count(const std::string& name) const { return command_.count(name); }
  /// Prints a status line to stderr unless --quiet.
  void status(std::string_view message) const;
  /// The command's one progress printer (see makeProgressPrinter()), shared by all its stages so
  /// that their lines follow one another.
  ProgressCallback progress() const;

 private:
  const GlobalOptions& options_;
  const CLI::App& command_;
  ProgressCallback progress_;
};

/// One sub-command: its name, help text, the advice printed when it runs out of memory (the
/// options that size its work), how it declares its options into `Arguments`, how it runs, and
/// which files it writes.
template <class Arguments>
struct CommandDefinition {
  std::string name;
  std::string description;
  std::string outOfMemoryAdvice;
  void (*declare)(CLI::App& command, Arguments& arguments);
  Report (*run)(const Arguments& arguments, const CommandContext& context);
  /// Every file the command writes with these arguments (not requested ones with an empty path),
  /// checked by checkOutputFiles() before `run` is called; null for a command that writes none.
  std::vector<OutputFile> (*outputs)(const Arguments& arguments) = nullptr;
};

/// The registered sub-commands. Each lives in its own .cc with one `add...Command` function that
/// calls add() with its CommandDefinition.
class CommandRegistry {
 public:
  CommandRegistry(CLI::App& app, const GlobalOptions& options) : app_(app), options_(options) {}

  /// Adds the sub-command of `definition` to the application: its options are declared now; when
  /// it was chosen, run() checks its outputs and calls its run function.
  template <class Arguments>
  void add(const CommandDefinition<Arguments>& definition) {
    auto arguments = std::make_shared<Arguments>();
    CLI::App* command = app_.add_subcommand(definition.name, definition.description);
    definition.declare(*command, *arguments);
    const auto run = definition.run;
    const auto outputs = definition.outputs;
    entries_.push_back({command, definition.outOfMemoryAdvice,
                        [arguments, run, outputs](const CommandContext& context) {
                          if (outputs != nullptr) checkOutputFiles(outputs(*arguments));
                          return run(*arguments, context);
                        }});
  }

  /// Runs the chosen sub-command (its outputs checked first), prints its report and returns its
  /// exit code; kUsageError when none was chosen. Exceptions propagate.
  int run() const;

  /// The chosen sub-command's name ("d2vdb" when none) and what to try when it runs out of memory.
  std::string chosenName() const;
  std::string outOfMemoryAdvice() const;

 private:
  struct Entry {
    CLI::App* command;
    std::string outOfMemoryAdvice;
    std::function<Report(const CommandContext&)> run;
  };
  const Entry* chosen() const;

  CLI::App& app_;
  const GlobalOptions& options_;
  std::vector<Entry> entries_;
};

/// Prints a status line to stderr unless --quiet.
void status(const GlobalOptions& options, std::string_view message);

/// Prints a warning to stderr (even with --quiet: warnings are not progress).
void warning(std::string_view message);

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

/// Declares --max-memory and --max-output into `budget` (on the top-level command, like --json):
/// byte counts as parseByteSize() reads them, 0 = no limit.
void declareBudgetOptions(CLI::App& app, ResourceBudget& budget);

/// Adds an option that reads exactly three comma- or space-separated numbers (e.g. "1,2,3").
CLI::Option* addVector3Option(CLI::App& app, const std::string& name, std::array<double, 3>& value,
                              const std::string& description);

// One registration function per sub-command (tools/cli/<Name>Command.cc).
void addInfoCommand(CommandRegistry& registry);
void addMesh2SdfCommand(CommandRegistry& registry);
void addPrimitiveCommand(CommandRegistry& registry);
void addConvertCommand(CommandRegistry& registry);
void addMeshCommand(CommandRegistry& registry);
void addSliceCommand(CommandRegistry& registry);
void addProjectCommand(CommandRegistry& registry);
void addHausdorffCommand(CommandRegistry& registry);
void addFitCurveCommand(CommandRegistry& registry);
void addFitSurfaceCommand(CommandRegistry& registry);
void addFieldCommand(CommandRegistry& registry);
void addQueryCommand(CommandRegistry& registry);
void addSmoothCommand(CommandRegistry& registry);
void addSupportCommand(CommandRegistry& registry);
void addOffsetCommand(CommandRegistry& registry);

}  // namespace d2vdb::cli
