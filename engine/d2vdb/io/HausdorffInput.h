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
#include "d2vdb/measure/MeshHausdorff.h"

namespace d2vdb {

/// The kinds a Hausdorff comparison takes: mesh, point set, level set, curve, surface, polylines.
InputKinds hausdorffInputKinds();

/// One side of a Hausdorff comparison as loaded.
struct HausdorffInput {
  InputKind kind = InputKind::Mesh;
  /// Mesh: the file's mesh; LevelSet: the engine's marching-cubes mesh of its zero set at the
  /// grid's resolution (extractIsoSurface(), iso-value 0). Empty for the other kinds.
  TriangleMesh mesh;
  std::vector<Eigen::Vector3d> points;    ///< PointSet: the points; Polylines: their vertices
  std::vector<TriangleIndices> segments;  ///< Polylines: (a, b, b) per segment
  std::optional<BSplineCurve> curve;      ///< Curve
  std::optional<BSplineSurface> surface;  ///< Surface
  /// A box that contains the shape (control points for splines, which contain them): the
  /// relative tolerance is taken of the diagonal of both inputs' boxes.
  Eigen::AlignedBox3d bounds;
};

/// Inputs from values in memory (InputError for an empty mesh or point set, or a level set
/// without a zero crossing; the level set is meshed here, `progress` seeing it).
HausdorffInput hausdorffInputOfMesh(TriangleMesh mesh);
HausdorffInput hausdorffInputOfPoints(std::vector<Eigen::Vector3d> points);
HausdorffInput hausdorffInputOfLevelSet(const openvdb::GridBase& grid,
                                        const ProgressCallback& progress = {});
HausdorffInput hausdorffInputOfCurve(BSplineCurve curve);
HausdorffInput hausdorffInputOfPolylines(const std::vector<Polyline>& polylines);
HausdorffInput hausdorffInputOfSurface(BSplineSurface surface);

/// Reads `path` as one of hausdorffInputKinds() (loadInput(), so errors are as there); a level set
/// is meshed here (InputError when its zero set is empty or cannot be meshed). `progress` sees the
/// meshing.
HausdorffInput loadHausdorffInput(const std::filesystem::path& path, const LoadOptions& options,
                                  const ProgressCallback& progress = {});

/// The input as triangles: meshes and points as they are, curves and surfaces tessellated to
/// within `tessellationError` world units (hausdorffShapeOfCurve(), hausdorffShapeOfSurface()).
HausdorffShape hausdorffShapeOf(const HausdorffInput& input, double tessellationError);

/// What a Hausdorff comparison of two inputs is asked for (`d2vdb hausdorff`'s options).
struct HausdorffRequest {
  /// Bracket width: world units, or relative to the diagonal of both inputs' boxes (their
  /// `bounds`) when `relative`. 0 means the default, relative 1e-6.
  double tolerance = 0.0;
  bool relative = false;
  bool oneSided = false;  ///< h(A -> B) only (A, if a spline, is then not tessellated)
  int maxDepth = 0;       ///< 0: CertifiedHausdorffOptions' default; else 1..40
  ProgressCallback progress;
};

/// Two inputs compared: their shapes, the tolerance used and the brackets.
struct HausdorffComparison {
  HausdorffShape a, b;
  double tolerance = 0.0;     ///< absolute, world units
  double diagonal = 0.0;      ///< of both inputs' bounds
  CertifiedHausdorff result;  ///< bToA left empty when one-sided
};

/// The certified Hausdorff bracket of two inputs, as `d2vdb hausdorff` computes it for every pair
/// but two curves: splines are measured from by their Bézier nets and measured to by triangles
/// within an eighth of the tolerance. InputError for a tolerance or depth out of range and as
/// certifiedHausdorff().
HausdorffComparison compareHausdorff(const HausdorffInput& a, const HausdorffInput& b,
                                     const HausdorffRequest& request);

/// The shape's triangles as a mesh (float positions), for heat maps of any kind of shape.
TriangleMesh meshOfShape(const HausdorffShape& shape);

}  // namespace d2vdb
