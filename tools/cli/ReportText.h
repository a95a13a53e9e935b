// Text of the sub-commands' reports that is printed before the report itself.
#pragma once

#include <string_view>

#include "Command.h"

namespace d2vdb::cli {

/// Prints the summary line `line` on stderr now, unless --quiet or --json (whose report stands
/// for the summary). For a summary line that must come before what the run prints later (a
/// warning), or that goes with an answer the report prints on stdout.
void printSummaryLineNow(const CommandContext& context, std::string_view line);

}  // namespace d2vdb::cli
