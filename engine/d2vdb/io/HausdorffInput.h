// Files as the certified Hausdorff distance compares them: meshes, point sets, level sets (their
// marching-cubes mesh), B-spline curves and surfaces (tessellated with a certified error).
#pragma once

#include <Eigen/Geometry>

#include <filesystem>
#include <optional>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/measure/HausdorffShape.h"

namespace d2vdb {

/// The kinds a Hausdorff comparison takes: mesh, point set, level set, curve, surface.
InputKinds hausdorffInputKinds();

/// One side of a Hausdorff comparison as loaded.
struct HausdorffInput {
  InputKind kind = InputKind::Mesh;
  /// Mesh: the file's mesh; LevelSet: the engine's marching-cubes mesh of its zero set at the
  /// grid's resolution (extractIsoSurface(), iso-value 0). Empty for the other kinds.
  TriangleMesh mesh;
  std::vector<Eigen::Vector3d> points;    ///< PointSet: the points
  std::optional<BSplineCurve> curve;      ///< Curve
  std::optional<BSplineSurface> surface;  ///< Surface
  /// A box that contains the shape (control points for splines, which contain them): the
  /// relative tolerance is taken of the diagonal of both inputs' boxes.
  Eigen::AlignedBox3d bounds;
};

/// Reads `path` as one of hausdorffInputKinds() (loadInput(), so errors are as there); a level set
/// is meshed here (InputError when its zero set is empty or cannot be meshed). `progress` sees the
/// meshing.
HausdorffInput loadHausdorffInput(const std::filesystem::path& path, const LoadOptions& options,
                                  const ProgressCallback& progress = {});

/// The input as triangles: meshes and points as they are, curves and surfaces tessellated to
/// within `tessellationError` world units (hausdorffShapeOfCurve(), hausdorffShapeOfSurface()).
HausdorffShape hausdorffShapeOf(const HausdorffInput& input, double tessellationError);

/// The shape's triangles as a mesh (float positions), for heat maps of any kind of shape.
TriangleMesh meshOfShape(const HausdorffShape& shape);

}  // namespace d2vdb
