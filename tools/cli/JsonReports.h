// JSON renderings of engine reports, shared by the sub-commands' --json output. The keys are the
// documented, stable output format (README, "JSON output").
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include <Eigen/Core>

#include "d2vdb/mesh/MeshValidation.h"

namespace d2vdb {
struct SignReport;  // d2vdb/field/MeshToLevelSet.h
}  // namespace d2vdb

namespace d2vdb::cli {

/// {"vertices", "triangles", "edges", "closed", "manifold", "oriented", "boundary_edges",
///  "boundary_loops", "non_manifold_edges", "non_manifold_vertices", "degenerate_triangles",
///  "inconsistently_oriented_edges", "unreferenced_vertices", "components", "euler_characteristic"}
nlohmann::json meshReportJson(const MeshReport& report);

/// {"method": "closest feature" | "winding number" | "none", "corrected_voxels",
///  "winding_number_queries", "reoriented_triangles", "watertight", "holes_closed",
///  "self_intersecting", "pockets_filled", "pocket_voxels", "hole_voxels"}: how mesh2sdf decided
///  inside and outside.
nlohmann::json signReportJson(const SignReport& report);

/// "signs checked by closest feature: N voxels of OpenVDB's conversion corrected\n" (text
/// reports of the commands that build a level set from a mesh).
std::string signSummary(const SignReport& report);

/// [x, y, z], or [x, y] when `dimension` is 2.
nlohmann::json pointJson(const Eigen::Vector3d& point, int dimension = 3);

/// The point of a JSON array [x, y, z] (as written by pointJson()).
Eigen::Vector3d pointFromJson(const nlohmann::json& values);

/// {"min": [x, y, z], "max": [x, y, z]}
nlohmann::json boxJson(const Eigen::Vector3d& min, const Eigen::Vector3d& max);

}  // namespace d2vdb::cli
