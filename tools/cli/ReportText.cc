#include "ReportText.h"

namespace d2vdb::cli {

void printSummaryLineNow(const CommandContext& context, std::string_view line) {
  if (!context.options().json) context.status(line);
}

}  // namespace d2vdb::cli
