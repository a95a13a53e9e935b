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

// What to try when a sub-command runs out of memory: the option that sizes its work.
std::string outOfMemoryAdvice(const std::string& subcommand) {
  if (subcommand == "mesh2sdf" || subcommand == "primitive") {
    return "use a coarser --voxel-size or --resolution, a smaller --half-width, or a lower "
           "--max-voxels to be refused early";
  }
  if (subcommand == "field") {
    return "use a coarser --voxel-size or --resolution, or a smaller --half-width";
  }
  if (subcommand == "fit-curve") {
    return "use fewer control points (--ctrl) or sensors (--sensors), or a smaller target";
  }
  if (subcommand == "hausdorff") {
    return "compare curves with fewer control points, or raise --tolerance";
  }
  if (subcommand == "mesh" || subcommand == "slice") {
    return "the level set is too large for this machine; mesh a coarser one";
  }
  return "the input is too large for this machine";
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

  CommandRegistry registry;
  addInfoCommand(app, registry, options);
  addMesh2SdfCommand(app, registry, options);
  addPrimitiveCommand(app, registry, options);
  addConvertCommand(app, registry, options);
  addMeshCommand(app, registry, options);
  addSliceCommand(app, registry, options);
  addProjectCommand(app, registry, options);
  addHausdorffCommand(app, registry, options);
  addFitCurveCommand(app, registry, options);
  addFitSurfaceCommand(app, registry, options);
  addFieldCommand(app, registry, options);
  addQueryCommand(app, registry, options);
  addSmoothCommand(app, registry, options);
  addSupportCommand(app, registry, options);
  addOffsetCommand(app, registry, options);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForAllHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForVersion& version) {
    return app.exit(version);
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
    for (const auto& [subcommand, body] : registry.commands) {
      if (subcommand->parsed()) return body();
    }
    std::cerr << "error: no sub-command given; run 'd2vdb --help'\n";
    return kUsageError;
  } catch (const CLI::Error& error) {
    std::cerr << "error: " << error.what() << "; run 'd2vdb "
              << app.get_subcommands().front()->get_name() << " --help'\n";
    return kUsageError;
  } catch (const d2vdb::InputError& error) {
    std::cerr << "error: " << error.what() << '\n';
    return kBadInput;
  } catch (const std::bad_alloc&) {
    const std::string name = app.get_subcommands().empty()
                                 ? std::string("d2vdb")
                                 : app.get_subcommands().front()->get_name();
    std::cerr << "error: out of memory in 'd2vdb " << name << "'; " << outOfMemoryAdvice(name)
              << '\n';
    return kRunFailure;
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << '\n';
    return kRunFailure;
  }
}
