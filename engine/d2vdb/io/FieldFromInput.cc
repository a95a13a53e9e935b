// The approximant field of any input (FieldFromInput.h).
#include "d2vdb/io/FieldFromInput.h"

#include <chrono>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/field/SmoothSurfaceField.h"
#include "d2vdb/io/PolylineFile.h"

namespace d2vdb {
namespace {

double voxelSizeFor(const FieldBuildOptions& options, const Eigen::AlignedBox3d& bounds,
                    const std::string& what) {
  return voxelSizeForBox(bounds.sizes().maxCoeff(), options.voxelSize, options.resolution, what);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

BuiltField smoothMeshField(const TriangleMesh& mesh, const std::filesystem::path& path,
                           const FieldBuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  double voxelSize = 0;
  SmoothSurfaceFromMeshOptions surfaceOptions;
  surfaceOptions.source = *options.smooth;
  surfaceOptions.label = path.string();
  surfaceOptions.beforeBuilding = [&](const HalfEdgeMesh&) {
    // The voxel size is refused before the expensive surface is built.
    Eigen::AlignedBox3d bounds;
    for (const Eigen::Vector3f& p : mesh.positions) bounds.extend(p.cast<double>());
    voxelSize = voxelSizeFor(options, bounds, "mesh");
  };
  const MeshSmoothSurface smooth = smoothSurfaceFromMesh(mesh, surfaceOptions, options.progress);
  SmoothFieldSurface report;
  report.source = *options.smooth;
  report.subdividedFaces = smooth.subdividedFaces;
  report.surfaceSeconds = secondsSince(start);
  ApproximantField field =
      smoothSurfaceField(smooth.surface, voxelSize, options.halfWidth, path.filename().string(),
                         options.field, options.progress);
  report.fieldSeconds = secondsSince(start) - report.surfaceSeconds;
  return BuiltField{std::move(field), InputKind::Mesh, {}, report};
}

BuiltField levelSetMeshField(const TriangleMesh& mesh, const FieldBuildOptions& options) {
  LevelSetOptions levelSet;
  levelSet.voxelSize = options.voxelSize;
  levelSet.resolution = options.voxelSize > 0 ? 0 : options.resolution;
  levelSet.halfWidth = options.halfWidth;
  levelSet.maxActiveVoxels = options.field.maxActiveVoxels;
  levelSet.maxMemoryBytes = options.field.maxMemoryBytes;
  levelSet.extraBytesPerVoxel = kApproximantBytesPerVoxel;
  LevelSetResult result = meshToLevelSet(mesh, levelSet, options.progress);
  return BuiltField{ApproximantField::fromLevelSet(result.grid, options.field, options.progress),
                    InputKind::Mesh, std::move(result.warnings), std::nullopt, result.signs};
}

BuiltField pointSetField(const std::vector<Eigen::Vector3d>& points,
                         const FieldBuildOptions& options) {
  Eigen::AlignedBox3d bounds;
  for (const Eigen::Vector3d& point : points) bounds.extend(point);
  const double voxelSize = voxelSizeFor(options, bounds, "point set");
  return BuiltField{ApproximantField::fromPoints(points, voxelSize, options.halfWidth,
                                                 options.field, options.progress),
                    InputKind::PointSet,
                    {},
                    std::nullopt};
}

BuiltField curveField(const CurveTarget& curve, InputKind kind, const FieldBuildOptions& options) {
  const double voxelSize = voxelSizeFor(options, curve.curveBounds(), "curve");
  return BuiltField{ApproximantField::fromCurve(curve, voxelSize, options.halfWidth, options.field,
                                                options.progress),
                    kind,
                    {},
                    std::nullopt};
}

}  // namespace

BuiltField buildApproximantField(LoadedInput input, const FieldBuildOptions& options) {
  const std::filesystem::path path = input.path;
  const InputKind kind = input.kind();
  if (options.smooth) {
    if (kind != InputKind::Mesh) {
      throw InputError("'" + path.string() + "' is " + describeInputKind(kind) +
                       "; the field of a smooth surface is built from a triangle mesh");
    }
    return smoothMeshField(std::move(input).take<MeshInput>().mesh, path, options);
  }
  switch (kind) {
    case InputKind::Field: {
      FieldInput field = std::move(input).take<FieldInput>();
      return BuiltField{std::move(field.field),
                        field.stored ? InputKind::Field : InputKind::LevelSet,
                        {},
                        std::nullopt};
    }
    case InputKind::Mesh:
      return levelSetMeshField(std::move(input).take<MeshInput>().mesh, options);
    case InputKind::PointSet:
      return pointSetField(std::move(input).take<PointSetInput>().points, options);
    case InputKind::Curve: {
      CurveTarget curve(std::move(input).take<BSplineCurve>(), options.field.domainPadding);
      curve.setLabel(path.filename().string());
      return curveField(curve, kind, options);
    }
    case InputKind::Polylines: {
      CurveTarget curve(onlyPolyline(std::move(input).take<PolylinesInput>().polylines, path),
                        options.field.domainPadding);
      curve.setLabel(path.filename().string());
      return curveField(curve, kind, options);
    }
    case InputKind::Surface:
      throw InputError("'" + path.string() +
                       "' is a B-spline surface; fields are built for curves, point sets and "
                       "closed surfaces given as meshes or level sets (tessellate it first)");
    default:
      break;
  }
  throw InputError("'" + path.string() + "' is " + describeInputKind(kind) +
                   "; fields are built for meshes, level sets, point sets, curves and polylines");
}

}  // namespace d2vdb
