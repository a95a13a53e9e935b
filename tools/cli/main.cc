// The d2vdb command: parses the command line, dispatches to one sub-command, maps failures to
// the documented exit codes (0 success, 1 usage, 2 bad input, 3 failure while running).
#include <tbb/global_control.h>

#include <exception>
#include <iostream>
#include <memory>
#include <new>
#include <string>

#include "Command.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/Version.h"

namespace {

// For a missing required argument, CLI11 says only "b is required": name what it is, from its
// help text ("missing b: Second curve (.json)"). Returns false when no missing argument of the
// chosen sub-command is found (another kind of RequiredError), which CLI11's message covers.
bool explainMissingArguments(const CLI::App& app) {
  bool found = false;
  for (const CLI::App* command : app.get_subcommands()) {
    for (const CLI::Option* option : command->get_options()) {
      if (!option->get_required() || option->count() > 0) continue;
      std::cerr << "error: missing " << option->get_name() << ": " << option->get_description()
                << "; run 'd2vdb " << command->get_name() << " --help'\n";
      found = true;
    }
  }
  return found;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace d2vdb::cli;
  CLI::App app{
      "d2vdb: sparse-grid implicit modelling engine. Distance fields in narrow-band OpenVDB "
      "grids,\n"
      "built from meshes and analytic shapes, read and written as .vdb files.\n"
      "Run 'd2vdb SUBCOMMAND --help' for the options of a sub-command."};
  app.set_version_flag("--version", std::string("d2vdb ") + d2vdb::kVersion);
  app.require_subcommand(1);
  app.fallthrough();  // global options may also follow the sub-command

  GlobalOptions options;
  app.add_option("--threads", options.threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  app.add_flag("-q,--quiet", options.quiet, "No progress or summary on stderr");
  app.add_flag("--json", options.json,
               "Print the sub-command's report as one JSON document on stdout");
  declareBudgetOptions(app, options.budget);

  CommandRegistry registry(app, options);
  using AddCommand = void (*)(CommandRegistry&);
  for (const AddCommand add :
       {addInfoCommand, addMesh2SdfCommand, addPrimitiveCommand, addConvertCommand, addMeshCommand,
        addSliceCommand, addProjectCommand, addHausdorffCommand, addFitCurveCommand,
        addFitSurfaceCommand, addFieldCommand, addQueryCommand, addSmoothCommand, addSupportCommand,
        addOffsetCommand}) {
    add(registry);
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForAllHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForVersion& version) {
    return app.exit(version);
  } catch (const CLI::RequiredError& error) {
    if (!explainMissingArguments(app)) app.exit(error);
    return kUsageError;
  } catch (const CLI::ParseError& error) {
    app.exit(error);
    return kUsageError;
  }

  std::unique_ptr<tbb::global_control> threadLimit;
  if (options.threads > 0) {
    threadLimit = std::make_unique<tbb::global_control>(
        tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(options.threads));
  }

  try {
    return registry.run();
  } catch (const CLI::Error& error) {
    std::cerr << "error: " << error.what() << "; run 'd2vdb "
              << app.get_subcommands().front()->get_name() << " --help'\n";
    return kUsageError;
  } catch (const d2vdb::InputError& error) {
    std::cerr << "error: " << error.what() << '\n';
    return kBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory in 'd2vdb " << registry.chosenName() << "'; "
              << registry.outOfMemoryAdvice() << '\n';
    return kRunFailure;
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << '\n';
    return kRunFailure;
  }
}
