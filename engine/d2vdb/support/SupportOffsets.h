// Offsets of support-function surfaces (h + d) and of sets of patches: which distances keep them
// regular, and their triangle meshes.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "d2vdb/core/ResourceBudget.h"
#include "d2vdb/mesh/MeshIO.h"
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

/// The vertex and triangle counts of tessellationDomain(patch, subdivisions) without building
/// it: the patch's own, else 10 * 4^s + 2 and 20 * 4^s. Doubles, so that they cannot overflow.
std::array<double, 2> tessellationDomainSize(const std::optional<SphericalTriangulation>& patch,
                                             int subdivisions);

/// Peak memory of tessellating one offset, bytes per domain vertex: the domain, the harmonics'
/// evaluation and the mesh. Measured 283 ('d2vdb offset' of a degree-8 sphere fit, --subdivisions
/// 6 against 7: 52.0 against 86.7 MB peak RSS for 40,962 against 163,842 vertices), rounded up.
inline constexpr double kSupportOffsetBytesPerVertex = 300.0;

/// Throws InputError, before the domain is built, when `count` offsets over
/// tessellationDomain(patch, subdivisions) would exceed `budget`: memory
/// kSupportOffsetBytesPerVertex per domain vertex, plus, for mesh outputs (`format` given), every
/// offset's mesh kept until all are written (24 bytes per vertex, 12 per triangle), plus
/// `bytesPerTriangle` per triangle of one offset for what the caller makes of it (e.g.
/// kLevelSetBytesPerTriangle for a level set); the files, for mesh outputs, by
/// estimateMeshFileBytes() (with normals) times `count`. The message names --subdivisions and the
/// largest value that fits.
void enforceSupportOffsetBudget(const std::optional<SphericalTriangulation>& patch,
                                int subdivisions, std::size_t count,
                                const std::optional<MeshFormat>& format, double bytesPerTriangle,
                                const ResourceBudget& budget);

/// The offset at `distance` of every patch of `set`, each tessellated over its own Gauss image
/// (tessellateSupport()), as one mesh of open pieces in patch order, with gaps where no patch
/// covers the surface. Throws InputError as tessellateSupport().
TriangleMesh tessellatePatchOffsets(const SupportPatchSet& set, double distance);

}  // namespace d2vdb
