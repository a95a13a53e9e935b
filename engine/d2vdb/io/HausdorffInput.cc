#include "d2vdb/io/HausdorffInput.h"

#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

Eigen::AlignedBox3d boxOf(const std::vector<Eigen::Vector3d>& points) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& point : points) box.extend(point);
  return box;
}

Eigen::AlignedBox3d boxOf(const TriangleMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3f& point : mesh.positions) box.extend(point.cast<double>());
  return box;
}

TriangleMesh meshOfLevelSet(const LevelSetInput& levelSet, const std::filesystem::path& path,
                            const ProgressCallback& progress) {
  IsoSurfaceOptions options;
  options.computeNormals = false;
  TriangleMesh mesh = extractIsoSurface(*levelSet.grid, options, progress);
  if (mesh.triangles.empty()) {
    throw InputError("the level set " + path.string() +
                     " has no zero crossing: there is no surface to compare");
  }
  return mesh;
}

}  // namespace

InputKinds hausdorffInputKinds() {
  return {InputKind::Mesh, InputKind::PointSet, InputKind::LevelSet, InputKind::Curve,
          InputKind::Surface};
}

HausdorffInput loadHausdorffInput(const std::filesystem::path& path, const LoadOptions& options,
                                  const ProgressCallback& progress) {
  LoadedInput loaded = loadInput(path, hausdorffInputKinds(), options);
  HausdorffInput input;
  input.kind = loaded.kind();
  switch (input.kind) {
    case InputKind::Mesh:
      input.mesh = std::move(loaded).take<MeshInput>().mesh;
      if (input.mesh.triangles.empty()) {
        throw InputError("the mesh " + path.string() + " has no triangles");
      }
      input.bounds = boxOf(input.mesh);
      break;
    case InputKind::PointSet:
      input.points = std::move(loaded).take<PointSetInput>().points;
      if (input.points.empty()) throw InputError("the point set " + path.string() + " is empty");
      input.bounds = boxOf(input.points);
      break;
    case InputKind::LevelSet:
      input.mesh = meshOfLevelSet(std::move(loaded).take<LevelSetInput>(), path, progress);
      input.bounds = boxOf(input.mesh);
      break;
    case InputKind::Curve:
      input.curve = std::move(loaded).take<BSplineCurve>();
      input.bounds = boxOf(input.curve->controlPoints());
      break;
    case InputKind::Surface:
      input.surface = std::move(loaded).take<BSplineSurface>();
      input.bounds = boxOf(input.surface->controlPoints());
      break;
    default:
      throw RuntimeFailure("loadHausdorffInput: unexpected input kind");
  }
  return input;
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
