#include "OutputFiles.h"

#include "d2vdb/core/OutputPath.h"

namespace d2vdb::cli {
namespace {

OutputPathRule ruleFor(const OutputFile& output) {
  OutputPathRule rule;
  rule.label = output.option;
  rule.reason = output.reason;
  switch (output.format) {
    case OutputFormat::Vdb:
      rule.extensions = {".vdb"};
      rule.content = "a .vdb file";
      break;
    case OutputFormat::Mesh:
      rule.extensions = {".obj", ".ply", ".stl"};
      rule.content = "a mesh";
      break;
    case OutputFormat::MeshOrVdb:
      rule.extensions = {".obj", ".ply", ".stl", ".vdb"};
      rule.content = "a mesh or a level set";
      break;
    case OutputFormat::ObjOrPly:
      rule.extensions = {".obj", ".ply"};
      rule.content = "a mesh with per-vertex data";
      break;
    case OutputFormat::Ply:
      rule.extensions = {".ply"};
      rule.content = "a PLY mesh";
      break;
    case OutputFormat::Json:
      rule.extensions = {".json"};
      rule.content = "JSON";
      break;
    case OutputFormat::Svg:
      rule.extensions = {".svg"};
      rule.content = "an SVG drawing";
      break;
    case OutputFormat::Table:
      rule.extensions = {".csv", ".json", ".ply"};
      rule.content = "a table of answers";
      break;
  }
  return rule;
}

}  // namespace

void checkOutputFiles(const std::vector<OutputFile>& outputs) {
  std::vector<OutputPathCheck> checks;
  checks.reserve(outputs.size());
  for (const OutputFile& output : outputs) checks.push_back({output.path, ruleFor(output)});
  checkOutputPaths(checks);
}

}  // namespace d2vdb::cli
