// Text of the sub-commands' reports that is printed before the report itself.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "Command.h"

namespace d2vdb::cli {

/// Prints the summary line `line` on stderr now, unless --quiet or --json (whose report stands
/// for the summary). For a summary line that must come before what the run prints later (a
/// warning), or that goes with an answer the report prints on stdout.
void printSummaryLineNow(const CommandContext& context, std::string_view line);

/// A run that read one input file and wrote one output file.
struct FileToFileRun {
  std::string input;
  std::string inputKind;  ///< inputKindName() of what the input was read as
  std::string output;
  double seconds = 0;
  std::vector<std::string> warnings;
};

/// Adds the run's keys to a report ("input", "input_kind", "output", "seconds", "warnings") and
/// returns the first line of its text, "wrote OUTPUT (KIND INPUT, SECONDS s):".
std::string addFileToFileKeys(nlohmann::json& json, const FileToFileRun& run);

}  // namespace d2vdb::cli
