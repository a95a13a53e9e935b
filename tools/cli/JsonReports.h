// JSON renderings of engine reports, shared by the sub-commands' --json output. The keys are the
// documented, stable output format (README, "JSON output").
#pragma once

#include <nlohmann/json.hpp>

#include "d2vdb/mesh/MeshMeasures.h"
#include "d2vdb/mesh/MeshValidation.h"

namespace d2vdb::cli {

/// {"vertices", "triangles", "edges", "closed", "manifold", "oriented", "boundary_edges",
///  "boundary_loops", "non_manifold_edges", "non_manifold_vertices", "degenerate_triangles",
///  "inconsistently_oriented_edges", "unreferenced_vertices", "components", "euler_characteristic"}
nlohmann::json meshReportJson(const MeshReport& report);

/// {"min": [x, y, z], "max": [x, y, z]}
nlohmann::json boundingBoxJson(const BoundingBox& box);

}  // namespace d2vdb::cli
