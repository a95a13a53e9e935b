#include "FieldReports.h"

#include "JsonReports.h"
#include "d2vdb/core/NumberFormat.h"

#include <sstream>

namespace d2vdb::cli {

nlohmann::json fieldJson(const ApproximantField& field) {
  const FieldStatistics statistics = field.statistics();
  nlohmann::json levels = nlohmann::json::array();
  for (const FieldLevelInfo& level : statistics.levels) {
    levels.push_back({{"level", level.level},
                      {"voxel_size", level.voxelSize},
                      {"half_width", level.halfWidth},
                      {"active_voxels", level.activeVoxels},
                      {"memory_bytes", level.memoryBytes},
                      {"distance_error_bound",
                       level.level == 0 ? 0.0 : field.coarseDistanceErrorBound(level.level)}});
  }
  const std::uint64_t bandVoxels =
      statistics.levels.empty() ? 0 : statistics.levels.front().activeVoxels;
  return {{"kind", targetKindName(statistics.kind)},
          {"estimator", statistics.estimator},
          {"voxel_size", field.voxelSize()},
          {"half_width", field.halfWidth()},
          {"domain", boxJson(field.domain().min(), field.domain().max())},
          {"levels", levels},
          {"coarse_levels_built", statistics.coarseLevelsBuilt},
          {"active_voxels", bandVoxels},
          {"memory_bytes", statistics.totalBytes},
          {"distance_grid_bytes", statistics.distanceGridBytes},
          {"dense_bytes", statistics.denseBytes},
          {"sample_error", field.sampleError()},
          {"flagged",
           {{"cut_locus", statistics.flaggedCutLocus},
            {"curvature_clamped", statistics.flaggedCurvatureClamped},
            {"degraded_estimate", statistics.flaggedDegraded}}}};
}

std::string fieldText(const nlohmann::json& report, const std::string& indent) {
  std::ostringstream text;
  const auto vector3 = [](const nlohmann::json& values) {
    return formatPoint(pointFromJson(values), 6);
  };
  const double memory = report.at("memory_bytes").get<double>();
  const double dense = report.at("dense_bytes").get<double>();
  text << indent << "kind            " << report.at("kind").get<std::string>() << '\n'
       << indent << "estimator       " << report.at("estimator").get<std::string>() << '\n'
       << indent << "voxel size      " << report.at("voxel_size").get<double>() << ", half-width "
       << report.at("half_width").get<double>() << " voxels\n"
       << indent << "domain          " << vector3(report.at("domain").at("min")) << " - "
       << vector3(report.at("domain").at("max")) << '\n';
  for (const nlohmann::json& level : report.at("levels")) {
    text << indent << "level " << level.at("level").get<int>() << "         voxel size "
         << level.at("voxel_size").get<double>() << ", "
         << level.at("active_voxels").get<std::uint64_t>() << " active voxels, "
         << level.at("memory_bytes").get<std::uint64_t>() << " bytes";
    if (level.at("level").get<int>() > 0) {
      text << ", distance error <= " << level.at("distance_error_bound").get<double>();
    }
    text << '\n';
  }
  const bool coarseBuilt = report.at("coarse_levels_built").get<bool>();
  if (!coarseBuilt) {
    text << indent << "coarse levels   not built yet: built on the first query beyond the band"
         << " (files do not store them)\n";
  }
  const nlohmann::json& flagged = report.at("flagged");
  text << indent << "memory          " << memory << " bytes"
       << (coarseBuilt ? "" : " without coarse levels")
       << " (a dense grid over the domain: " << dense << " bytes, "
       << (memory > 0 ? dense / memory : 0.0) << "x more)\n"
       << indent << "flagged voxels  " << flagged.at("cut_locus").get<std::uint64_t>()
       << " cut locus, " << flagged.at("curvature_clamped").get<std::uint64_t>()
       << " curvature clamped, " << flagged.at("degraded_estimate").get<std::uint64_t>()
       << " degraded estimate\n";
  return text.str();
}

nlohmann::json flagNamesJson(std::uint16_t flags) {
  static constexpr std::pair<ApproximantFlag, const char*> kNames[] = {
      {kFlagCutLocus, "cut_locus"},
      {kFlagCurvatureClamped, "curvature_clamped"},
      {kFlagDegradedEstimate, "degraded_estimate"},
      {kFlagFarField, "far_field"},
      {kFlagEndPoint, "end_point"},
  };
  nlohmann::json names = nlohmann::json::array();
  for (const auto& [flag, name] : kNames) {
    if ((flags & flag) != 0) names.push_back(name);
  }
  return names;
}

nlohmann::json quadraticFormJson(const QuadraticForm& form) {
  nlohmann::json rows = nlohmann::json::array();
  for (int row = 0; row < 3; ++row) {
    rows.push_back({form.A(row, 0), form.A(row, 1), form.A(row, 2)});
  }
  return {{"A", rows}, {"b", pointJson(form.b)}, {"c", form.c}};
}

}  // namespace d2vdb::cli
