#include "ReportText.h"

namespace d2vdb::cli {

void printSummaryLineNow(const CommandContext& context, std::string_view line) {
  if (!context.options().json) context.status(line);
}

std::string addFileToFileKeys(nlohmann::json& json, const FileToFileRun& run) {
  json["input"] = run.input;
  json["input_kind"] = run.inputKind;
  json["output"] = run.output;
  json["seconds"] = run.seconds;
  json["warnings"] = run.warnings;
  return "wrote " + run.output + " (" + run.inputKind + " " + run.input + ", " +
         std::to_string(run.seconds) + " s):";
}

}  // namespace d2vdb::cli
