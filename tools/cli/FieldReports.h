// JSON and text renderings of squared-distance approximant fields and approximants, shared by
// `d2vdb field`, `d2vdb query` and `d2vdb info`. The keys are the documented, stable output
// format (README, "JSON output").
#pragma once

#include <nlohmann/json.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/field/ApproximantField.h"

namespace d2vdb::cli {

/// {"kind", "estimator", "voxel_size", "half_width", "domain", "levels": [{"level",
///  "voxel_size", "half_width", "active_voxels", "memory_bytes", "distance_error_bound"}],
///  "active_voxels" (band), "memory_bytes" (all levels), "distance_grid_bytes", "dense_bytes",
///  "sample_error", "flagged": {"cut_locus", "curvature_clamped", "degraded_estimate"}}
nlohmann::json fieldJson(const ApproximantField& field);

/// Several indented lines describing fieldJson(field) for people.
std::string fieldText(const nlohmann::json& fieldReport, const std::string& indent);

/// Names of the set ApproximantFlag bits, e.g. ["cut_locus", "far_field"].
nlohmann::json flagNamesJson(std::uint16_t flags);

/// {"A": [[...], [...], [...]], "b": [x, y, z], "c": c}
nlohmann::json quadraticFormJson(const QuadraticForm& form);

}  // namespace d2vdb::cli
