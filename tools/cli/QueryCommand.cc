// d2vdb query: the approximant of a field at one point: distance, footpoint, frame, curvatures,
// flags and the quadratic forms the fitters minimise.
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

#include "Command.h"
#include "FieldReports.h"
#include "JsonReports.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/field/Approximant.h"
#include "d2vdb/io/InputFile.h"

namespace d2vdb::cli {
namespace {

std::string vectorText(const Eigen::Vector3d& value) {
  return formatPoint(value, 9);
}

std::string formText(const char* name, const QuadraticForm& form) {
  std::ostringstream text;
  text << std::setprecision(9) << "  " << name << " form  Q(x) = x^T A x - 2 b.x + c\n";
  for (int row = 0; row < 3; ++row) {
    text << "    A[" << row << "]  " << form.A(row, 0) << ' ' << form.A(row, 1) << ' '
         << form.A(row, 2) << '\n';
  }
  text << "    b     " << vectorText(form.b) << "\n    c     " << form.c << '\n';
  return text.str();
}

}  // namespace

void addQueryCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  struct Arguments {
    std::string field, form = "sdm";
    std::vector<double> point;
  };
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "query",
      "Print the squared-distance approximant of a field (.vdb written by 'd2vdb field', or a\n"
      "plain level set) at a world point: the level that answered (0 = the narrow band), the\n"
      "distance, footpoint, normal and tangent (e1), curvatures (curves: curvature and principal\n"
      "normal), flags and the SDM quadratic form (A, b, c); --form all adds PDM and TDM.\n"
      "A point outside the field's working domain is an error (exit code 2).\n"
      "Example: d2vdb query torus-field.vdb 1.4 0 0.1\n"
      "         d2vdb query torus-field.vdb -1.4 0 -0.1 --json --form all");
  command->add_option("field", args->field, "Field .vdb file")->required();
  command->add_option("point", args->point, "World coordinates X Y Z of the query point")
      ->required()
      ->expected(3);
  command->add_option("--form", args->form, "Quadratic forms to print: sdm or all")
      ->capture_default_str()
      ->check(CLI::IsMember({"sdm", "all"}));
  command->add_flag("--json", options.json, "Print one JSON document on stdout");

  registry.add(command, [args, &options]() {
    const Eigen::Vector3d point(args->point[0], args->point[1], args->point[2]);
    if (!point.allFinite()) throw InputError("the query point must have finite coordinates");
    LoadOptions load;
    load.purpose = "the field given to 'd2vdb query'";
    load.progress = makeProgressPrinter(options);
    const ApproximantField field = loadInputAs<FieldInput>(args->field, load).field;
    ApproximantField::Accessor accessor(field);
    const Approximant approximant = accessor.approximantAt(point);
    const bool curve = approximant.kind == TargetKind::Curve;
    const bool surface = approximant.kind == TargetKind::Surface;

    nlohmann::json forms = {{"sdm", quadraticFormJson(approximant.form(ErrorTerm::SDM))}};
    if (args->form == "all") {
      forms["pdm"] = quadraticFormJson(approximant.form(ErrorTerm::PDM));
      forms["tdm"] = quadraticFormJson(approximant.form(ErrorTerm::TDM));
    }
    nlohmann::json report = {
        {"field", args->field},
        {"point", pointJson(point)},
        {"kind", targetKindName(approximant.kind)},
        {"level", accessor.lastLevel()},
        {"distance", approximant.distance},
        {"origin", pointJson(approximant.origin)},
        {"footpoint", pointJson(approximant.footpoint)},
        {"normal", pointJson(approximant.normal)},
        {"tangent", pointJson(approximant.tangent)},
        {"bitangent", pointJson(approximant.bitangent())},
        {"flags", flagNamesJson(approximant.flags)},
        {"sdm_weights", pointJson(approximant.sdmWeights())},
        {"squared_distance_estimate", approximant.form(ErrorTerm::SDM)(point)},
        {"forms", forms},
    };
    if (surface) {
      report["k1"] = approximant.k1;
      report["k2"] = approximant.k2;
    }
    if (curve) {
      report["curvature"] = approximant.k1;
      report["principal_normal"] = pointJson(approximant.principalNormal);
    }
    if (options.json) {
      printJson(report);
      return kSuccess;
    }
    std::ostringstream text;
    text << std::setprecision(9) << args->field << " at " << vectorText(point) << ": "
         << targetKindName(approximant.kind) << " field, level " << accessor.lastLevel()
         << (accessor.lastLevel() == 0 ? " (narrow band)" : " (beyond the band)") << '\n'
         << "  distance         " << approximant.distance << '\n'
         << "  footpoint        " << vectorText(approximant.footpoint) << '\n'
         << "  normal           " << vectorText(approximant.normal) << '\n'
         << "  " << (surface ? "e1 (principal)  " : "tangent         ") << ' '
         << vectorText(approximant.tangent) << '\n';
    if (surface) {
      text << "  curvatures       k1 " << approximant.k1 << ", k2 " << approximant.k2 << '\n';
    }
    if (curve) {
      text << "  curvature        " << approximant.k1 << '\n'
           << "  principal normal " << vectorText(approximant.principalNormal) << '\n';
    }
    std::string flags;
    for (const nlohmann::json& name : report["flags"]) {
      flags += (flags.empty() ? "" : ", ") + name.get<std::string>();
    }
    text << "  flags            " << (flags.empty() ? "none" : flags) << '\n'
         << "  SDM weights      " << vectorText(approximant.sdmWeights()) << '\n'
         << formText("SDM", approximant.form(ErrorTerm::SDM));
    if (args->form == "all") {
      text << formText("PDM", approximant.form(ErrorTerm::PDM))
           << formText("TDM", approximant.form(ErrorTerm::TDM));
    }
    std::cout << text.str();
    return kSuccess;
  });
}

// TRANSITION: the old registration until this command has its CommandDefinition.
void addQueryCommand(CommandRegistry& registry) {
  addQueryCommand(registry.app(), registry, registry.legacyOptions());
}

}  // namespace d2vdb::cli
