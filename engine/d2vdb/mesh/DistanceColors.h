// Meshes coloured by a per-vertex distance (a heat map): the "distance" property and vertex
// colours that MeshLab, Blender and Houdini read from a PLY.
#pragma once

#include <array>
#include <cstdint>
#include <functional>

#include <Eigen/Core>

#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// Blue (distance <= -scale) through white (0) to red (>= scale), linear in distance / scale;
/// white for a scale that is not positive. Never throws.
std::array<std::uint8_t, 3> distanceColor(double distance, double scale);

/// The vertex attributes of `mesh` coloured by `distance` (world units, signed or not) at each
/// vertex: scalar "distance" (0 where `distance` is not finite) and distanceColor() scaled by the
/// largest |distance|. `largest` receives that value (0 for a mesh at distance 0 everywhere).
VertexAttributes distanceAttributes(const TriangleMesh& mesh,
                                    const std::function<double(const Eigen::Vector3d&)>& distance,
                                    double& largest);

}  // namespace d2vdb
