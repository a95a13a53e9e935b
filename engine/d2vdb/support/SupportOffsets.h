// Offsets of support-function surfaces (h + d) and of sets of patches: which distances keep them
// regular, and their triangle meshes.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"
#include "d2vdb/support/SphericalTriangulation.h"
#include "d2vdb/support/SupportPatches.h"
#include "d2vdb/support/SupportValidity.h"

namespace d2vdb {

/// Checks every one of `distances` with requireRegularOffset() when `validity` is regular (a
/// singular function has been refused or warned about by its own check). A distance outside the
/// safe range throws InputError saying what to do (a distance inside the range, or the command's
/// --allow-singular); with `allowSingular` each becomes a warning appended to `warnings`.
void requireRegularOffsets(const SupportValidity& validity, const std::vector<double>& distances,
                           bool allowSingular, std::vector<std::string>& warnings);

/// As requireRegularOffsets() for the patches of `set`: every distance must lie inside
/// (set.safeOffsetMin(), set.safeOffsetMax()), where every patch stays regular.
void requireRegularPatchOffsets(const SupportPatchSet& set, const std::vector<double>& distances,
                                bool allowSingular, std::vector<std::string>& warnings);

/// The normals the offsets of a support function are tessellated over: `patch` (the Gauss image it
/// was fitted over) when given, else geodesicSphere(subdivisions), 10 * 4^s + 2 normals.
SphericalTriangulation tessellationDomain(const std::optional<SphericalTriangulation>& patch,
                                          int subdivisions);

/// The offset at `distance` of every patch of `set`, each tessellated over its own Gauss image
/// (tessellateSupport()), as one mesh of open pieces in patch order, with gaps where no patch
/// covers the surface. Throws InputError as tessellateSupport().
TriangleMesh tessellatePatchOffsets(const SupportPatchSet& set, double distance);

}  // namespace d2vdb
