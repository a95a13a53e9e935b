// d2vdb query: the approximant of a field at one point: distance, footpoint, frame, curvatures,
// flags and the quadratic forms the fitters minimise.
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "Command.h"
#include "FieldReports.h"
#include "JsonReports.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/field/Approximant.h"
#include "d2vdb/io/InputFile.h"

namespace d2vdb::cli {
namespace {

struct QueryArguments {
  std::string field, form = "sdm";
  std::vector<double> point;
};

/// Significant digits of the text report.
constexpr int kDigits = 9;

void declareQuery(CLI::App& command, QueryArguments& args) {
  command.add_option("field", args.field, "Field .vdb file")->required();
  command.add_option("point", args.point, "World coordinates X Y Z of the query point")
      ->required()
      ->expected(3);
  command.add_option("--form", args.form, "Quadratic forms to print: sdm or all")
      ->capture_default_str()
      ->check(CLI::IsMember({"sdm", "all"}));
}

/// The approximant at the query point, and the level of the field that answered.
struct QueryAnswer {
  Eigen::Vector3d point;
  Approximant approximant;
  int level = 0;
};

nlohmann::json queryJson(const QueryArguments& args, const QueryAnswer& answer) {
  const Approximant& approximant = answer.approximant;
  nlohmann::json forms = {{"sdm", quadraticFormJson(approximant.form(ErrorTerm::SDM))}};
  if (args.form == "all") {
    forms["pdm"] = quadraticFormJson(approximant.form(ErrorTerm::PDM));
    forms["tdm"] = quadraticFormJson(approximant.form(ErrorTerm::TDM));
  }
  nlohmann::json report = {
      {"field", args.field},
      {"point", pointJson(answer.point)},
      {"kind", targetKindName(approximant.kind)},
      {"level", answer.level},
      {"distance", approximant.distance},
      {"origin", pointJson(approximant.origin)},
      {"footpoint", pointJson(approximant.footpoint)},
      {"normal", pointJson(approximant.normal)},
      {"tangent", pointJson(approximant.tangent)},
      {"bitangent", pointJson(approximant.bitangent())},
      {"flags", flagNamesJson(approximant.flags)},
      {"sdm_weights", pointJson(approximant.sdmWeights())},
      {"squared_distance_estimate", approximant.form(ErrorTerm::SDM)(answer.point)},
      {"forms", forms},
  };
  if (approximant.kind == TargetKind::Surface) {
    report["k1"] = approximant.k1;
    report["k2"] = approximant.k2;
  }
  if (approximant.kind == TargetKind::Curve) {
    report["curvature"] = approximant.k1;
    report["principal_normal"] = pointJson(approximant.principalNormal);
  }
  return report;
}

std::string formText(const char* name, const QuadraticForm& form) {
  std::ostringstream text;
  text << std::setprecision(kDigits) << "  " << name << " form  Q(x) = x^T A x - 2 b.x + c\n";
  for (int row = 0; row < 3; ++row) {
    text << "    A[" << row << "]  " << form.A(row, 0) << ' ' << form.A(row, 1) << ' '
         << form.A(row, 2) << '\n';
  }
  text << "    b     " << formatPoint(form.b, kDigits) << "\n    c     " << form.c << '\n';
  return text.str();
}

// The names of `flags` (ApproximantFlag bits) separated by commas, or "none".
std::string flagsText(std::uint16_t flags) {
  std::string names;
  for (const nlohmann::json& name : flagNamesJson(flags)) {
    names += (names.empty() ? "" : ", ") + name.get<std::string>();
  }
  return names.empty() ? "none" : names;
}

std::string queryText(const QueryArguments& args, const QueryAnswer& answer) {
  const Approximant& approximant = answer.approximant;
  const bool surface = approximant.kind == TargetKind::Surface;
  std::ostringstream text;
  text << std::setprecision(kDigits) << args.field << " at " << formatPoint(answer.point, kDigits)
       << ": " << targetKindName(approximant.kind) << " field, level " << answer.level
       << (answer.level == 0 ? " (narrow band)" : " (beyond the band)") << '\n'
       << "  distance         " << approximant.distance << '\n'
       << "  footpoint        " << formatPoint(approximant.footpoint, kDigits) << '\n'
       << "  normal           " << formatPoint(approximant.normal, kDigits) << '\n'
       << "  " << (surface ? "e1 (principal)  " : "tangent         ") << ' '
       << formatPoint(approximant.tangent, kDigits) << '\n';
  if (surface) {
    text << "  curvatures       k1 " << approximant.k1 << ", k2 " << approximant.k2 << '\n';
  }
  if (approximant.kind == TargetKind::Curve) {
    text << "  curvature        " << approximant.k1 << '\n'
         << "  principal normal " << formatPoint(approximant.principalNormal, kDigits) << '\n';
  }
  text << "  flags            " << flagsText(approximant.flags) << '\n'
       << "  SDM weights      " << formatPoint(approximant.sdmWeights(), kDigits) << '\n'
       << formText("SDM", approximant.form(ErrorTerm::SDM));
  if (args.form == "all") {
    text << formText("PDM", approximant.form(ErrorTerm::PDM))
         << formText("TDM", approximant.form(ErrorTerm::TDM));
  }
  return text.str();
}

Report runQuery(const QueryArguments& args, const CommandContext& context) {
  QueryAnswer answer;
  answer.point = Eigen::Vector3d(args.point[0], args.point[1], args.point[2]);
  if (!answer.point.allFinite()) {
    throw InputError("the query point must have finite coordinates");
  }
  LoadOptions load;
  load.purpose = "the field given to 'd2vdb query'";
  load.progress = context.progress();
  const ApproximantField field = loadInputAs<FieldInput>(args.field, load).field;
  ApproximantField::Accessor accessor(field);
  answer.approximant = accessor.approximantAt(answer.point);
  answer.level = accessor.lastLevel();
  return {queryJson(args, answer), queryText(args, answer), Report::Text::Answer};
}

}  // namespace

void addQueryCommand(CommandRegistry& registry) {
  registry.add<QueryArguments>(
      {"query",
       "Print the squared-distance approximant of a field (.vdb written by 'd2vdb field', or a\n"
       "plain level set) at a world point: the level that answered (0 = the narrow band), the\n"
       "distance, footpoint, normal and tangent (e1), curvatures (curves: curvature and principal\n"
       "normal), flags and the SDM quadratic form (A, b, c); --form all adds PDM and TDM.\n"
       "A point outside the field's working domain is an error (exit code 2).\n"
       "Example: d2vdb query torus-field.vdb 1.4 0 0.1\n"
       "         d2vdb query torus-field.vdb -1.4 0 -0.1 --json --form all",
       "the input is too large for this machine", declareQuery, runQuery});
}

}  // namespace d2vdb::cli
