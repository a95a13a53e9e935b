// An approximant field (field/ApproximantField.h) as standard OpenVDB grids, the form a field
// takes in a .vdb file (FieldFile.h), and back.
#pragma once

#include <openvdb/openvdb.h>

#include <string>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/ApproximantField.h"

namespace d2vdb {

/// Metadata keys of a field's distance grid.
inline constexpr const char* kFieldKindMetadata = "d2vdb_field_kind";  ///< surface/curve/points
inline constexpr const char* kFieldEstimatorMetadata = "d2vdb_field_estimator";  ///< one line
inline constexpr const char* kFieldVersionMetadata = "d2vdb_field_version";      ///< int, 2
inline constexpr const char* kFieldDomainMinMetadata = "d2vdb_domain_min";       ///< vec3d, world
inline constexpr const char* kFieldDomainMaxMetadata = "d2vdb_domain_max";       ///< vec3d, world
/// The version of the layout below that fieldToGrids() writes. fieldFromGrids() also reads
/// version 1, whose "flags" grid was Int32 (a type pyopenvdb and other clients cannot open).
inline constexpr int kFieldFormatVersion = 2;

/// The band of `field` as standard OpenVDB grids: first the distance grid (a shallow copy of
/// field.distanceGrid() sharing its tree, named "surface" or "unsigned_distance" when it has no
/// name, with the metadata above), then companion grids that share its transform and active
/// topology, every band voxel active in each, values in world units and the world frame:
/// surfaces "normal" (Vec3s, outward unit normal), "k1", "k2" (float, principal curvatures,
/// 1 / world units), "e1" (Vec3s, first principal direction); curves "direction" (Vec3s, unit
/// vector from the footpoint toward the voxel centre), "tangent" (Vec3s), "curvature" (float),
/// "principal_normal" (Vec3s, zero where the curvature is 0); points "direction" (Vec3s); and
/// "flags" (float holding the ApproximantFlag bits as a whole number, 0 where none is set: float so
/// that every client opens it; exact, also as half floats, for values below 2048). The coarse
/// levels are not stored (a field rebuilds them on its first query beyond the band). Never throws
/// for a valid field.
openvdb::GridPtrVec fieldToGrids(const ApproximantField& field);

/// The field whose grids fieldToGrids() made (any order, extra grids ignored; companion grids are
/// matched to the distance grid voxel by voxel), with bit-for-bit the same answers; or, when no
/// float grid carries kFieldKindMetadata, the field of the first float level set
/// (ApproximantField::fromLevelSet(), approximants computed now). `source` names the file in
/// messages; options apply as in fromLevelSet(), except that a stored field keeps its stored
/// working domain. Throws InputError for a missing or mismatched companion grid (wrong type,
/// different active voxels or transform), non-finite values or normals that are not unit vectors,
/// active tiles, an empty band, missing metadata, an unknown field kind or version, or grids that
/// hold neither a field nor a level set.
ApproximantField fieldFromGrids(const openvdb::GridPtrVec& grids, const std::string& source,
                                const ApproximantFieldOptions& options = {},
                                const ProgressCallback& progress = {});

}  // namespace d2vdb
