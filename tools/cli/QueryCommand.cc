// d2vdb query: the approximant of a field at one point (distance, footpoint, frame, curvatures,
// flags and the quadratic forms the fitters minimise), or at every point of a point file, written
// to a result file.
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
#include "d2vdb/io/FieldFileQuery.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/QueryResultFile.h"

namespace d2vdb::cli {
namespace {

struct QueryArguments {
  std::string field, form = "sdm";
  std::vector<double> point;
  std::string points, out;  ///< batch mode: the point file and the result file
};

/// Significant digits of the text report.
constexpr int kAnswerDigits = 9;

void declareQuery(CLI::App& command, QueryArguments& args) {
  command.add_option("field", args.field, "Field .vdb file")->required();
  auto* point =
      command.add_option("point", args.point, "World coordinates X Y Z of the query point")
          ->expected(3);
  auto* points =
      command
          .add_option("--points", args.points,
                      "Batch mode: answer every point of this .xyz or .ply file (instead of X Y Z)")
          ->excludes(point);
  auto* out = command.add_option(
      "--out", args.out,
      "Batch mode: the result file, .csv, .json or .ply by extension (written atomically)");
  points->needs(out);
  out->needs(points);
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
  text << std::setprecision(kAnswerDigits) << "  " << name << " form  Q(x) = x^T A x - 2 b.x + c\n";
  for (int row = 0; row < 3; ++row) {
    text << "    A[" << row << "]  " << form.A(row, 0) << ' ' << form.A(row, 1) << ' '
         << form.A(row, 2) << '\n';
  }
  text << "    b     " << formatPoint(form.b, kAnswerDigits) << "\n    c     " << form.c << '\n';
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
  text << std::setprecision(kAnswerDigits) << args.field << " at "
       << formatPoint(answer.point, kAnswerDigits) << ": " << targetKindName(approximant.kind)
       << " field, level " << answer.level
       << (answer.level == 0 ? " (narrow band)" : " (beyond the band)") << '\n'
       << "  distance         " << approximant.distance << '\n'
       << "  footpoint        " << formatPoint(approximant.footpoint, kAnswerDigits) << '\n'
       << "  normal           " << formatPoint(approximant.normal, kAnswerDigits) << '\n'
       << "  " << (surface ? "e1 (principal)  " : "tangent         ") << ' '
       << formatPoint(approximant.tangent, kAnswerDigits) << '\n';
  if (surface) {
    text << "  curvatures       k1 " << approximant.k1 << ", k2 " << approximant.k2 << '\n';
  }
  if (approximant.kind == TargetKind::Curve) {
    text << "  curvature        " << approximant.k1 << '\n'
         << "  principal normal " << formatPoint(approximant.principalNormal, kAnswerDigits)
         << '\n';
  }
  text << "  flags            " << flagsText(approximant.flags) << '\n'
       << "  SDM weights      " << formatPoint(approximant.sdmWeights(), kAnswerDigits) << '\n'
       << formText("SDM", approximant.form(ErrorTerm::SDM));
  if (args.form == "all") {
    text << formText("PDM", approximant.form(ErrorTerm::PDM))
         << formText("TDM", approximant.form(ErrorTerm::TDM));
  }
  return text.str();
}

LoadOptions fieldLoadOptions(const CommandContext& context) {
  LoadOptions load;
  load.purpose = "the field given to 'd2vdb query'";
  load.progress = context.progress();
  return load;
}

/// Batch mode: every point of args.points answered into args.out.
Report runBatchQuery(const QueryArguments& args, const CommandContext& context) {
  // Refuse what can be refused before the field is read: the result format, then the points.
  queryResultFormat(args.out);
  const std::vector<Eigen::Vector3d> points = readPointSet(args.points);
  const ApproximantField field =
      loadInputAs<FieldInput>(args.field, fieldLoadOptions(context)).field;
  QueryResultOptions options;
  options.allForms = args.form == "all";
  options.field = args.field;
  const QueryResultSummary summary = writeFieldQueries(args.out, field, points, options);
  nlohmann::json levels = nlohmann::json::array();
  for (const std::uint64_t count : summary.levels) levels.push_back(count);
  const nlohmann::json json = {{"field", args.field},
                               {"points", args.points},
                               {"output", args.out},
                               {"kind", targetKindName(field.kind())},
                               {"count", summary.count},
                               {"answered", summary.answered},
                               {"outside_domain", summary.outsideDomain},
                               {"levels", levels}};
  std::ostringstream text;
  text << args.out << ": " << summary.count << " points of " << args.points << ", "
       << summary.answered << " answered, " << summary.outsideDomain
       << " outside the working domain\n";
  return {json, text.str(), Report::Text::Answer};
}

Report runQuery(const QueryArguments& args, const CommandContext& context) {
  if (!args.points.empty()) return runBatchQuery(args, context);
  if (args.point.size() != 3) {
    throw InputError("'d2vdb query' needs the point X Y Z, or --points FILE --out FILE");
  }
  QueryAnswer answer;
  answer.point = Eigen::Vector3d(args.point[0], args.point[1], args.point[2]);
  if (!answer.point.allFinite()) {
    throw InputError("the query point must have finite coordinates");
  }
  // Reads only the part of a field file the point needs (bitwise the answer of the whole file).
  const FieldFileAnswer read =
      answerFromFieldFile(args.field, answer.point, fieldLoadOptions(context));
  if (read.answer.status != QueryStatus::Ok) throw InputError(read.outsideMessage);
  answer.approximant = read.answer.approximant;
  answer.level = read.answer.level;
  return {queryJson(args, answer), queryText(args, answer), Report::Text::Answer};
}

std::vector<OutputFile> outputsOfQuery(const QueryArguments& args) {
  return {{"--out", args.out, OutputFormat::Table}};
}

}  // namespace

void addQueryCommand(CommandRegistry& registry) {
  registry.add<QueryArguments>(
      {"query",
       "Print the squared-distance approximant of a field (.vdb written by 'd2vdb field', or a\n"
       "plain level set) at a world point: the level that answered (0 = the narrow band), the\n"
       "distance, footpoint, normal and tangent (e1), curvatures (curves: curvature and principal\n"
       "normal), flags and the SDM quadratic form (A, b, c); --form all adds PDM and TDM.\n"
       "A point outside the field's working domain is an error (exit code 2). A field file\n"
       "written by 'd2vdb field' is read only around the point (same answer as a full read).\n"
       "Batch mode: --points P.xyz|P.ply --out R.csv|R.json|R.ply answers every point of P\n"
       "in parallel (the same call, the same numbers) into R, one record per point in file\n"
       "order; columns: x y z status level distance squared_distance_estimate origin_* \n"
       "footpoint_* normal_* tangent_* bitangent_* k1 k2 principal_normal_* flags\n"
       "sdm_weights_1..3 sdm_A_xx..zz (9) sdm_b_* sdm_c (--form all: pdm_*, tdm_* too); a point\n"
       "outside the domain gets status outside_domain and no values (README: query results).\n"
       "Example: d2vdb query torus-field.vdb 1.4 0 0.1\n"
       "         d2vdb query torus-field.vdb -1.4 0 -0.1 --json --form all\n"
       "         d2vdb query torus-field.vdb --points volumes/scan.xyz --out answers.csv",
       "the input is too large for this machine", declareQuery, runQuery, outputsOfQuery});
}

}  // namespace d2vdb::cli
