// The genus of a closed orientable triangle mesh, from its validation report.
#pragma once

#include <optional>

#include "d2vdb/mesh/MeshValidation.h"

namespace d2vdb {

/// True when `report` describes a closed, 2-manifold, consistently oriented mesh: a closed
/// orientable surface (what marching cubes gives for a closed level set), the kind of mesh that
/// has a genus.
bool isClosedOrientedManifold(const MeshReport& report);

/// The total genus of the surface `report` describes: the sum over its C connected components of
/// (2 - chi_i) / 2, i.e. (2 C - chi) / 2 for the total Euler characteristic chi (each closed
/// orientable component has chi_i = 2 - 2 g_i): 0 for a sphere, 1 for a torus, also 1 for a sphere
/// and a torus together. std::nullopt unless isClosedOrientedManifold(report). Never throws.
std::optional<long> surfaceGenus(const MeshReport& report);

}  // namespace d2vdb
