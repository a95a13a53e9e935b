// The squared-distance approximant field of any input loadInput() returns, in one call: meshes
// (through their level set, or projected onto their smooth surface), level sets and stored
// fields, point sets, B-spline curves and polylines.
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/field/VoxelBudget.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/manifold/SmoothSurfaceFromMesh.h"

namespace d2vdb {

/// How buildApproximantField() sizes and builds a field.
struct FieldBuildOptions {
  /// Voxel edge length of the band (world units); 0 = the longest side of the target's bounding
  /// box over `resolution` (voxelSizeForBox(); a box of zero extent is an InputError). Not used
  /// for .vdb inputs: their field keeps the level set's voxels. Meshes made into a level set take
  /// voxelSize and resolution as meshToLevelSet() does.
  double voxelSize = 0;
  /// Voxels along the longest side of the target's bounding box, used when voxelSize is 0.
  int resolution = kDefaultResolution;
  /// Narrow-band half-width in voxels.
  double halfWidth = 3;
  /// The field's working domain and voxel limit. domainPadding also pads a curve target's domain
  /// (CurveTarget.h); maxActiveVoxels also limits a mesh's level set (meshToLevelSet()).
  ApproximantFieldOptions field;
  /// Meshes: build the field of the mesh's smooth surface from this source
  /// (smoothSurfaceFromMesh(), then smoothSurfaceField()) instead of its level set. Only meshes
  /// are accepted then.
  std::optional<SmoothSurfaceSource> smooth;
  /// Progress of the level set, the smooth surface and the field (may be empty).
  ProgressCallback progress;
};

/// How a field's smooth surface was built (FieldBuildOptions::smooth).
struct SmoothFieldSurface {
  SmoothSurfaceSource source = SmoothSurfaceSource::LoopLimit;
  /// Loop limit surface: faces evaluated on one Loop subdivision step (0 for PN triangles).
  std::size_t subdividedFaces = 0;
  double surfaceSeconds = 0;  ///< wall clock: the half-edge mesh, the source and the surface
  double fieldSeconds = 0;    ///< wall clock: the field
};

/// What buildApproximantField() built.
struct BuiltField {
  ApproximantField field;
  /// What the field is of: Mesh, PointSet, Curve, Polylines, LevelSet (a level set .vdb whose
  /// approximants were computed by loadInput()) or Field (a field the file stored).
  InputKind inputKind = InputKind::Mesh;
  std::vector<std::string> warnings;  ///< one sentence each (meshToLevelSet()'s)
  std::optional<SmoothFieldSurface> smooth;
  /// Meshes made into a level set: how its signs were decided and how many voxels were corrected.
  std::optional<SignReport> signs = std::nullopt;
};

/// Builds the approximant field of `input`, as loaded by loadInput() (InputFile.h) with the kinds
/// Mesh, PointSet, Field, Curve and Polylines accepted (only Mesh with options.smooth), and with
/// LoadOptions::field = options.field, since a .vdb input is made into its field as it is read:
/// - a mesh: its level set (meshToLevelSet() with voxelSize or resolution, halfWidth and
///   field.maxActiveVoxels), then ApproximantField::fromLevelSet(); with options.smooth, its smooth
///   surface (smoothSurfaceFromMesh(), labelled with the file's path) and smoothSurfaceField()
///   (labelled with the file's name);
/// - a field: as loaded;
/// - a point set: ApproximantField::fromPoints();
/// - a curve or the one polyline of a polyline file: a CurveTarget (domain padding
///   field.domainPadding, labelled with the file's name), then ApproximantField::fromCurve().
/// Throws InputError for a B-spline surface ("tessellate it first"), another kind, a polyline file
/// without exactly one polyline, and as the builders named above do (an empty or degenerate
/// target, a voxel size that is not positive, a band over the voxel limit, a mesh that is not
/// closed and manifold with options.smooth).
BuiltField buildApproximantField(LoadedInput input, const FieldBuildOptions& options);

}  // namespace d2vdb
