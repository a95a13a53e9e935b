#include "d2vdb/io/HausdorffInput.h"

#include "d2vdb/contour/IsoSurface.h"

#include <cmath>
#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/MeshMeasures.h"

namespace d2vdb {
namespace {

Eigen::AlignedBox3d boxOf(const std::vector<Eigen::Vector3d>& points) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& point : points) box.extend(point);
  return box;
}

// The box of the vertices the triangles use (mesh/MeshMeasures.h), as the shape is.
Eigen::AlignedBox3d boxOf(const TriangleMesh& mesh) {
  const BoundingBox box = boundingBox(mesh);
  return Eigen::AlignedBox3d(box.min, box.max);
}

}  // namespace

InputKinds hausdorffInputKinds() {
  return {InputKind::Mesh,  InputKind::PointSet, InputKind::LevelSet,
          InputKind::Curve, InputKind::Surface,  InputKind::Polylines};
}

HausdorffInput hausdorffInputOfMesh(TriangleMesh mesh) {
  if (mesh.triangles.empty()) throw InputError("the mesh has no triangles");
  HausdorffInput input;
  input.kind = InputKind::Mesh;
  input.bounds = boxOf(mesh);
  input.mesh = std::move(mesh);
  return input;
}

HausdorffInput hausdorffInputOfPoints(std::vector<Eigen::Vector3d> points) {
  if (points.empty()) throw InputError("the point set is empty");
  HausdorffInput input;
  input.kind = InputKind::PointSet;
  input.bounds = boxOf(points);
  input.points = std::move(points);
  return input;
}

HausdorffInput hausdorffInputOfLevelSet(const openvdb::GridBase& grid,
                                        const ProgressCallback& progress) {
  IsoSurfaceOptions options;
  options.computeNormals = false;
  HausdorffInput input;
  input.kind = InputKind::LevelSet;
  input.mesh = extractIsoSurface(grid, options, progress);
  if (input.mesh.triangles.empty()) {
    throw InputError("the level set has no zero crossing: there is no surface to compare");
  }
  input.bounds = boxOf(input.mesh);
  return input;
}

HausdorffInput hausdorffInputOfCurve(BSplineCurve curve) {
  HausdorffInput input;
  input.kind = InputKind::Curve;
  input.bounds = boxOf(curve.controlPoints());
  input.curve = std::move(curve);
  return input;
}

HausdorffInput hausdorffInputOfPolylines(const std::vector<Polyline>& polylines) {
  HausdorffInput input;
  input.kind = InputKind::Polylines;
  for (const Polyline& polyline : polylines) {
    const auto first = static_cast<TriangleMesh::Index>(input.points.size());
    const auto count = static_cast<TriangleMesh::Index>(polyline.points.size());
    input.points.insert(input.points.end(), polyline.points.begin(), polyline.points.end());
    for (TriangleMesh::Index k = 0; k + 1 < count; ++k) {
      input.segments.push_back({first + k, first + k + 1, first + k + 1});
    }
    if (polyline.closed && count > 2) input.segments.push_back({first + count - 1, first, first});
    if (count == 1) input.segments.push_back({first, first, first});
  }
  if (input.segments.empty()) throw InputError("the polyline file holds no points");
  input.bounds = boxOf(input.points);
  return input;
}

HausdorffInput hausdorffInputOfSurface(BSplineSurface surface) {
  HausdorffInput input;
  input.kind = InputKind::Surface;
  input.bounds = boxOf(surface.controlPoints());
  input.surface = std::move(surface);
  return input;
}

HausdorffInput loadHausdorffInput(const std::filesystem::path& path, const LoadOptions& options,
                                  const ProgressCallback& progress) {
  LoadedInput loaded = loadInput(path, hausdorffInputKinds(), options);
  const std::string named = " (" + path.string() + ")";
  try {
    switch (loaded.kind()) {
      case InputKind::Mesh:
        return hausdorffInputOfMesh(std::move(loaded).take<MeshInput>().mesh);
      case InputKind::PointSet:
        return hausdorffInputOfPoints(std::move(loaded).take<PointSetInput>().points);
      case InputKind::LevelSet:
        return hausdorffInputOfLevelSet(*std::move(loaded).take<LevelSetInput>().grid, progress);
      case InputKind::Curve:
        return hausdorffInputOfCurve(std::move(loaded).take<BSplineCurve>());
      case InputKind::Surface:
        return hausdorffInputOfSurface(std::move(loaded).take<BSplineSurface>());
      case InputKind::Polylines:
        return hausdorffInputOfPolylines(std::move(loaded).take<PolylinesInput>().polylines);
      default:
        throw RuntimeFailure("loadHausdorffInput: unexpected input kind");
    }
  } catch (const InputError& error) {
    throw InputError(std::string(error.what()) + named);
  }
}

HausdorffComparison compareHausdorff(const HausdorffInput& a, const HausdorffInput& b,
                                     const HausdorffRequest& request) {
  if (request.tolerance < 0.0 || !std::isfinite(request.tolerance)) {
    throw InputError("the Hausdorff tolerance must be a positive finite number");
  }
  if (request.maxDepth < 0 || request.maxDepth > 40) {
    throw InputError("the Hausdorff subdivision depth must be 1..40 for these shapes");
  }
  Eigen::AlignedBox3d box = a.bounds;
  box.extend(b.bounds);
  HausdorffComparison comparison;
  comparison.diagonal = box.diagonal().norm();
  const bool relative = request.relative || request.tolerance == 0.0;
  const double requested = request.tolerance > 0.0 ? request.tolerance : 1e-6;
  comparison.tolerance =
      relative ? requested * (comparison.diagonal > 0.0 ? comparison.diagonal : 1.0) : requested;
  // A spline is measured from by its Bézier nets (exactly) and measured to by triangles within an
  // eighth of the tolerance (the bracket then has at least half the tolerance left); one-sided,
  // A is only measured from and needs no triangles.
  comparison.a = hausdorffShapeOf(a, request.oneSided ? 0.0 : comparison.tolerance / 8.0);
  comparison.b = hausdorffShapeOf(b, comparison.tolerance / 8.0);
  CertifiedHausdorffOptions options;
  options.tolerance = comparison.tolerance;
  options.relative = false;
  if (request.maxDepth > 0) options.maxDepth = request.maxDepth;
  options.progress = request.progress;
  CertifiedHausdorff& result = comparison.result;
  if (request.oneSided) {
    result.aToB = directedHausdorff(comparison.a, comparison.b, comparison.tolerance, options);
    result.lower = result.aToB.lower;
    result.upper = result.aToB.upper;
    result.tolerance = comparison.tolerance;
  } else {
    result = certifiedHausdorff(comparison.a, comparison.b, options);
  }
  return comparison;
}

HausdorffShape hausdorffShapeOf(const HausdorffInput& input, double tessellationError) {
  switch (input.kind) {
    case InputKind::Mesh:
      return hausdorffShapeOfMesh(input.mesh);
    case InputKind::LevelSet: {
      HausdorffShape shape = hausdorffShapeOfMesh(input.mesh);
      shape.description = "marching-cubes mesh of the level set's zero set";
      return shape;
    }
    case InputKind::PointSet:
      return hausdorffShapeOfPoints(input.points);
    case InputKind::Polylines: {
      HausdorffShape shape;
      shape.points = input.points;
      shape.triangles = input.segments;
      shape.description = "polylines";
      return shape;
    }
    case InputKind::Curve:
      return hausdorffShapeOfCurve(*input.curve, tessellationError);
    case InputKind::Surface:
      return hausdorffShapeOfSurface(*input.surface, tessellationError);
    default:
      throw RuntimeFailure("hausdorffShapeOf: unexpected input kind");
  }
}

TriangleMesh meshOfShape(const HausdorffShape& shape) {
  TriangleMesh mesh;
  mesh.positions.reserve(shape.points.size());
  for (const Eigen::Vector3d& point : shape.points) mesh.positions.push_back(point.cast<float>());
  for (const TriangleIndices& triangle : shape.triangles) {
    if (triangle[0] != triangle[1] && triangle[1] != triangle[2] && triangle[0] != triangle[2]) {
      mesh.triangles.push_back(triangle);
    }
  }
  return mesh;
}

}  // namespace d2vdb
