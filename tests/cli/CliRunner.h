// Runs the built d2vdb command from tests and captures its exit code and output.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace d2vdb::test {

/// What one run of the command produced.
struct CliResult {
  int exitCode = -1;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// Reads a whole file; empty string if it does not exist.
inline std::string readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

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

}  // namespace d2vdb::test
