// d2vdb info: reports on a .vdb file (grids, types, class, voxel size, active voxels, bounding
// boxes, memory, metadata), a mesh file (counts and a closed/manifold report), a B-spline .json or
// a support-function file (its validity over its domain).
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "Command.h"
#include "FieldReports.h"
#include "JsonReports.h"
#include "SupportReports.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/FieldGrids.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/io/SupportInput.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshMeasures.h"
#include "d2vdb/mesh/MeshValidation.h"
#include "d2vdb/spline/CurvePolyline.h"

namespace d2vdb::cli {
namespace {

struct InfoArguments {
  std::string file;
};

void declareInfo(CLI::App& command, InfoArguments& args) {
  command.add_option("file", args.file, "File to describe")->required();
}

Eigen::Vector3d toEigen(const openvdb::Vec3d& value) {
  return {value.x(), value.y(), value.z()};
}

// {"min": [i, j, k], "max": [i, j, k]} as integers.
nlohmann::json indexBoxJson(const openvdb::CoordBBox& box) {
  return {{"min", {box.min().x(), box.min().y(), box.min().z()}},
          {"max", {box.max().x(), box.max().y(), box.max().z()}}};
}

nlohmann::json gridInfoJson(const VdbGridInfo& grid) {
  nlohmann::json metadata = nlohmann::json::object();
  for (const auto& [key, value] : grid.metadata) metadata[key] = value;
  return {
      {"name", grid.name},
      {"value_type", grid.valueType},
      {"class", grid.gridClass},
      {"voxel_size", pointJson(toEigen(grid.voxelSize))},
      {"active_voxels", grid.activeVoxelCount},
      {"index_bbox", indexBoxJson(grid.indexBoundingBox)},
      {"world_bbox",
       boxJson(toEigen(grid.worldBoundingBox.min()), toEigen(grid.worldBoundingBox.max()))},
      {"memory_bytes", grid.memoryBytes},
      {"metadata", metadata},
  };
}

std::string vector3Text(const nlohmann::json& values) {
  return formatPoint(pointFromJson(values), 6);
}

std::string vdbText(const nlohmann::json& report) {
  std::ostringstream out;
  out << report.at("file").get<std::string>() << ": " << report.at("grids").size() << " grid(s)\n";
  for (const nlohmann::json& grid : report.at("grids")) {
    out << "  grid '" << grid.at("name").get<std::string>() << "'\n"
        << "    type            " << grid.at("value_type").get<std::string>() << '\n'
        << "    class           " << grid.at("class").get<std::string>() << '\n'
        << "    voxel size      " << vector3Text(grid.at("voxel_size")) << '\n'
        << "    active voxels   " << grid.at("active_voxels").get<std::uint64_t>() << '\n'
        << "    index bbox      " << vector3Text(grid.at("index_bbox").at("min")) << " - "
        << vector3Text(grid.at("index_bbox").at("max")) << '\n'
        << "    world bbox      " << vector3Text(grid.at("world_bbox").at("min")) << " - "
        << vector3Text(grid.at("world_bbox").at("max")) << '\n'
        << "    memory          " << grid.at("memory_bytes").get<std::uint64_t>() << " bytes\n";
    for (const auto& [key, value] : grid.at("metadata").items()) {
      out << "    meta " << key << " = " << value.get<std::string>() << '\n';
    }
  }
  return out.str();
}

std::string meshText(const nlohmann::json& report, const MeshReport& meshReport) {
  std::ostringstream out;
  out << report.at("file").get<std::string>() << ": " << report.at("format").get<std::string>()
      << " mesh, " << report.at("vertices").get<std::size_t>() << " vertices, "
      << report.at("triangles").get<std::size_t>() << " triangles\n"
      << "  closed " << (meshReport.closed ? "yes" : "no") << ", manifold "
      << (meshReport.manifold ? "yes" : "no") << ", consistently oriented "
      << (meshReport.oriented ? "yes" : "no") << ", components "
      << meshReport.connectedComponentCount << ", Euler characteristic "
      << meshReport.eulerCharacteristic << '\n'
      << "  bounding box " << vector3Text(report.at("bbox").at("min")) << " - "
      << vector3Text(report.at("bbox").at("max")) << ", surface area "
      << report.at("surface_area").get<double>() << '\n';
  const std::string problems = meshReport.problems();
  if (!problems.empty()) {
    std::istringstream lines(problems);
    for (std::string line; std::getline(lines, line);) out << "  problem: " << line << '\n';
  }
  return out.str();
}

// For a .vdb holding an approximant field (isFieldFile()): the field's summary (FieldReports.h)
// plus "distance_grid" and "companion_grids"; when the field cannot be rebuilt (missing or
// mismatched companion grids), "error" says why instead.
std::optional<nlohmann::json> fieldReport(const std::filesystem::path& path,
                                          const std::vector<openvdb::GridBase::Ptr>& grids) {
  if (!isFieldFile(grids)) return std::nullopt;
  const std::string distance = findGrid(grids)->getName();
  nlohmann::json report;
  try {
    const ApproximantField field = fieldFromGrids(grids, path.string());
    field.buildCoarseLevels();  // info shows every level
    report = fieldJson(field);
  } catch (const InputError& error) {
    report = {{"error", error.what()}};
  }
  report["distance_grid"] = distance;
  nlohmann::json companions = nlohmann::json::array();
  for (const openvdb::GridBase::Ptr& grid : grids) {
    if (grid->getName() != distance) companions.push_back(grid->getName());
  }
  report["companion_grids"] = companions;
  return report;
}

std::string fieldInfoText(const nlohmann::json& field) {
  std::ostringstream out;
  out << "  approximant field (distance grid '" << field.at("distance_grid").get<std::string>()
      << "')\n";
  if (field.contains("error")) {
    out << "    cannot be rebuilt: " << field.at("error").get<std::string>() << '\n';
  } else {
    out << fieldText(field, "    ");
  }
  std::string companions;
  for (const nlohmann::json& name : field.at("companion_grids")) {
    companions += (companions.empty() ? "" : ", ") + name.get<std::string>();
  }
  out << "    companion grids " << (companions.empty() ? "none" : companions) << '\n';
  return out.str();
}

nlohmann::json splineJson(const Spline& spline) {
  if (const auto* curve = std::get_if<BSplineCurve>(&spline)) {
    return {{"kind", "bspline_curve"},
            {"dimension", curve->dimension()},
            {"degree", curve->degree()},
            {"closed", curve->isClosed()},
            {"control_points", curve->controlPointCount()},
            {"knots", curve->knots().size()},
            {"domain", {curve->domain().start, curve->domain().end}},
            {"length_estimate", sampledLength(*curve)}};
  }
  const auto& surface = std::get<BSplineSurface>(spline);
  return {{"kind", "bspline_surface"},
          {"degree", {surface.degreeU(), surface.degreeV()}},
          {"closed", {surface.isClosedU(), surface.isClosedV()}},
          {"control_points", {surface.countU(), surface.countV()}},
          {"knots", {surface.knotsU().size(), surface.knotsV().size()}},
          {"domain_u", {surface.domainU().start, surface.domainU().end}},
          {"domain_v", {surface.domainV().start, surface.domainV().end}}};
}

Report vdbReport(const std::string& file, const std::vector<openvdb::GridBase::Ptr>& grids) {
  Report report;
  report.json = {{"file", file}, {"kind", "vdb"}, {"grids", nlohmann::json::array()}};
  for (const VdbGridInfo& grid : summarizeGrids(grids)) {
    report.json["grids"].push_back(gridInfoJson(grid));
  }
  if (const auto field = fieldReport(file, grids)) report.json["field"] = *field;
  report.text = vdbText(report.json);
  if (report.json.contains("field")) report.text += fieldInfoText(report.json.at("field"));
  return report;
}

Report meshInfoReport(const std::string& file, const MeshInput& input) {
  const TriangleMesh& mesh = input.mesh;
  const MeshReport meshReport = validateMesh(mesh);
  Report report;
  report.json = meshReportJson(meshReport);
  report.json["file"] = file;
  report.json["kind"] = "mesh";
  report.json["format"] = meshFormatName(input.format);
  report.json["has_normals"] = mesh.hasNormals();
  const BoundingBox bounds = boundingBox(mesh);
  report.json["bbox"] = boxJson(bounds.min, bounds.max);
  report.json["surface_area"] = surfaceArea(mesh);
  report.text = meshText(report.json, meshReport);
  return report;
}

Report splineReport(const std::string& file, const Spline& spline) {
  Report report;
  report.json = splineJson(spline);
  report.json["file"] = file;
  report.text = file + ":\n";
  for (const auto& [key, value] : report.json.items()) {
    if (key != "file") {
      report.text += "  " + key + " " +
                     value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + '\n';
    }
  }
  return report;
}

Report supportInfoReport(const std::string& file, SupportFunctionDocument document) {
  Report report;
  report.json = supportFileReport(file, analyzeSupportDocument(std::move(document)));
  report.text = file + ": support function\n" + supportText(report.json, "  ");
  return report;
}

Report runInfo(const InfoArguments& args, const CommandContext&) {
  LoadOptions load;
  load.purpose = "the file given to 'd2vdb info'";
  LoadedInput input = loadInput(args.file,
                                {InputKind::VdbGrids, InputKind::Mesh, InputKind::Curve,
                                 InputKind::Surface, InputKind::SupportFunction},
                                load);
  Report report;
  switch (input.kind()) {
    case InputKind::VdbGrids:
      report = vdbReport(args.file, std::move(input).take<VdbGridsInput>().grids);
      break;
    case InputKind::Mesh:
      report = meshInfoReport(args.file, std::move(input).take<MeshInput>());
      break;
    case InputKind::SupportFunction:
      report = supportInfoReport(args.file, std::move(input).take<SupportFunctionDocument>());
      break;
    case InputKind::Curve:
      report = splineReport(args.file, Spline(std::move(input).take<BSplineCurve>()));
      break;
    default:
      report = splineReport(args.file, Spline(std::move(input).take<BSplineSurface>()));
      break;
  }
  report.textKind = Report::Text::Answer;
  return report;
}

}  // namespace

void addInfoCommand(CommandRegistry& registry) {
  registry.add<InfoArguments>(
      {"info",
       "Report on a file: for .vdb the grids (type, class, voxel size, active voxels, bounding "
       "boxes, memory, metadata; for a field written by 'd2vdb field' also its kind, estimator, "
       "levels, domain and companion grids); for meshes (.obj, .ply, .stl) the counts and whether "
       "the mesh "
       "is closed, manifold and consistently oriented; for B-spline curve/surface .json files "
       "their degree, control points, knots and domain.\n"
       "Example: d2vdb info volumes/bunny.vdb --json",
       "", declareInfo, runInfo});
}

}  // namespace d2vdb::cli
