// Runs the built d2vdb command from tests and captures its exit code and output; the fixture of
// the CLI tests (a scratch directory to run in).
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "common/ScratchDirectory.h"

namespace d2vdb::test {

/// What one run of the command produced.
struct CliResult {
  int exitCode = -1;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// Runs `d2vdb ARGS` through the shell (arguments are passed verbatim: quote paths with spaces),
/// with stdout and stderr captured into files under `scratch`.
inline CliResult runCli(const std::string& arguments, const std::filesystem::path& scratch) {
  const std::filesystem::path outPath = scratch / "cli.stdout";
  const std::filesystem::path errPath = scratch / "cli.stderr";
  const std::string command = std::string("'") + D2VDB_CLI + "' " + arguments + " >'" +
                              outPath.string() + "' 2>'" + errPath.string() + "' </dev/null";
  const int status = std::system(command.c_str());
  CliResult result;
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.out = readWholeFile(outPath);
  result.err = readWholeFile(errPath);
  return result;
}

/// Fixture of the CLI tests: a fresh scratch directory (ScratchDirectoryTest) where the command
/// runs and its output is captured.
class CliFixture : public ScratchDirectoryTest {
 protected:
  /// Runs `d2vdb ARGS` (runCli()).
  CliResult run(const std::string& arguments) const { return runCli(arguments, scratch_); }
  /// `name` inside the scratch directory, quoted for the shell.
  std::string path(const std::string& name) const { return "'" + file(name).string() + "'"; }
};

}  // namespace d2vdb::test
