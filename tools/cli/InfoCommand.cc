// d2vdb info: reports on a .vdb file (grids, types, class, voxel size, active voxels, bounding
// boxes, memory, metadata) or a mesh file (counts and a closed/manifold report).
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "Command.h"
#include "FieldReports.h"
#include "JsonReports.h"
#include "SupportInputs.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/FieldGrids.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshMeasures.h"
#include "d2vdb/mesh/MeshValidation.h"

namespace d2vdb::cli {
namespace {

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

void printVdbText(const nlohmann::json& report) {
  std::cout << report.at("file").get<std::string>() << ": " << report.at("grids").size()
            << " grid(s)\n";
  for (const nlohmann::json& grid : report.at("grids")) {
    std::cout << "  grid '" << grid.at("name").get<std::string>() << "'\n"
              << "    type            " << grid.at("value_type").get<std::string>() << '\n'
              << "    class           " << grid.at("class").get<std::string>() << '\n'
              << "    voxel size      " << vector3Text(grid.at("voxel_size")) << '\n'
              << "    active voxels   " << grid.at("active_voxels").get<std::uint64_t>() << '\n'
              << "    index bbox      " << vector3Text(grid.at("index_bbox").at("min")) << " - "
              << vector3Text(grid.at("index_bbox").at("max")) << '\n'
              << "    world bbox      " << vector3Text(grid.at("world_bbox").at("min")) << " - "
              << vector3Text(grid.at("world_bbox").at("max")) << '\n'
              << "    memory          " << grid.at("memory_bytes").get<std::uint64_t>()
              << " bytes\n";
    for (const auto& [key, value] : grid.at("metadata").items()) {
      std::cout << "    meta " << key << " = " << value.get<std::string>() << '\n';
    }
  }
}

void printMeshText(const nlohmann::json& report, const MeshReport& meshReport) {
  std::cout << report.at("file").get<std::string>() << ": "
            << report.at("format").get<std::string>() << " mesh, "
            << report.at("vertices").get<std::size_t>() << " vertices, "
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
    for (std::string line; std::getline(lines, line);) std::cout << "  problem: " << line << '\n';
  }
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

void printFieldText(const nlohmann::json& field) {
  std::cout << "  approximant field (distance grid '"
            << field.at("distance_grid").get<std::string>() << "')\n";
  if (field.contains("error")) {
    std::cout << "    cannot be rebuilt: " << field.at("error").get<std::string>() << '\n';
  } else {
    std::cout << fieldText(field, "    ");
  }
  std::string companions;
  for (const nlohmann::json& name : field.at("companion_grids")) {
    companions += (companions.empty() ? "" : ", ") + name.get<std::string>();
  }
  std::cout << "    companion grids " << (companions.empty() ? "none" : companions) << '\n';
}

nlohmann::json splineJson(const Spline& spline) {
  if (const auto* curve = std::get_if<BSplineCurve>(&spline)) {
    const std::vector<Eigen::Vector3d> points = curve->sample(1025);
    double polylineLength = 0;
    for (std::size_t i = 1; i < points.size(); ++i)
      polylineLength += (points[i] - points[i - 1]).norm();
    return {{"kind", "bspline_curve"},
            {"dimension", curve->dimension()},
            {"degree", curve->degree()},
            {"closed", curve->isClosed()},
            {"control_points", curve->controlPointCount()},
            {"knots", curve->knots().size()},
            {"domain", {curve->domain().start, curve->domain().end}},
            {"length_estimate", polylineLength}};
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

int runInfo(const std::string& file, const GlobalOptions& options) {
  const std::filesystem::path path(file);
  // Support-function files are JSON with their own "type", read by the support commands' reader.
  if (isSupportFunctionFile(file)) {
    const nlohmann::json report = supportFileReport(file);
    if (options.json) {
      printJson(report);
    } else {
      std::cout << file << ": support function\n" << supportText(report, "  ");
    }
    return kSuccess;
  }
  LoadOptions load;
  load.purpose = "the file given to 'd2vdb info'";
  LoadedInput input = loadInput(
      path, {InputKind::VdbGrids, InputKind::Mesh, InputKind::Curve, InputKind::Surface}, load);
  if (input.kind() == InputKind::VdbGrids) {
    const std::vector<openvdb::GridBase::Ptr> grids = std::move(input).take<VdbGridsInput>().grids;
    nlohmann::json report = {{"file", file}, {"kind", "vdb"}, {"grids", nlohmann::json::array()}};
    for (const VdbGridInfo& grid : summarizeGrids(grids)) {
      report["grids"].push_back(gridInfoJson(grid));
    }
    if (const auto field = fieldReport(path, grids)) report["field"] = *field;
    if (options.json) {
      printJson(report);
    } else {
      printVdbText(report);
      if (report.contains("field")) printFieldText(report.at("field"));
    }
    return kSuccess;
  }
  if (input.kind() == InputKind::Mesh) {
    const MeshInput meshInput = std::move(input).take<MeshInput>();
    const TriangleMesh& mesh = meshInput.mesh;
    const MeshReport meshReport = validateMesh(mesh);
    nlohmann::json report = meshReportJson(meshReport);
    report["file"] = file;
    report["kind"] = "mesh";
    report["format"] = meshFormatName(meshInput.format);
    report["has_normals"] = mesh.hasNormals();
    const BoundingBox bounds = boundingBox(mesh);
    report["bbox"] = boxJson(bounds.min, bounds.max);
    report["surface_area"] = surfaceArea(mesh);
    if (options.json) {
      printJson(report);
    } else {
      printMeshText(report, meshReport);
    }
    return kSuccess;
  }
  {
    const Spline spline = input.kind() == InputKind::Curve
                              ? Spline(std::move(input).take<BSplineCurve>())
                              : Spline(std::move(input).take<BSplineSurface>());
    nlohmann::json report = splineJson(spline);
    report["file"] = file;
    if (options.json) {
      printJson(report);
    } else {
      std::cout << file << ":\n";
      for (const auto& [key, value] : report.items()) {
        if (key != "file")
          std::cout << "  " << key << " "
                    << value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
      }
    }
    return kSuccess;
  }
}

}  // namespace

void addInfoCommand(CLI::App& app, CommandRegistry& registry, GlobalOptions& options) {
  auto file = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand(
      "info",
      "Report on a file: for .vdb the grids (type, class, voxel size, active voxels, bounding "
      "boxes, memory, metadata; for a field written by 'd2vdb field' also its kind, estimator, "
      "levels, domain and companion grids); for meshes (.obj, .ply, .stl) the counts and whether "
      "the mesh "
      "is closed, manifold and consistently oriented; for B-spline curve/surface .json files "
      "their degree, control points, knots and domain.\n"
      "Example: d2vdb info volumes/bunny.vdb --json");
  command->add_option("file", *file, "File to describe")->required();
  command->add_flag("--json", options.json, "Print one JSON document on stdout");
  registry.add(command, [file, &options]() { return runInfo(*file, options); });
}

// TRANSITION: the old registration until this command has its CommandDefinition.
void addInfoCommand(CommandRegistry& registry) {
  addInfoCommand(registry.app(), registry, registry.legacyOptions());
}

}  // namespace d2vdb::cli
