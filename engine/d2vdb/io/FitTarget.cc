// Reading the target of a fit (FitTarget.h).
#include "d2vdb/io/FitTarget.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/field/SurfaceTarget.h"
#include "d2vdb/fit/InitialCurve.h"
#include "d2vdb/io/PolylineFile.h"

namespace d2vdb {
namespace {

// Spacing of a curve target's samples, as a fraction of its length.
constexpr double kCurveSampleFraction = 1.0 / 2000.0;
// Parameter grid of a B-spline surface target's samples.
constexpr int kSurfaceSamplesPerDirection = 101;
// About this many samples of a surface field's zero level set.
constexpr std::size_t kFieldSurfaceSamples = 200000;

/// Samples of a field's zero level set: footpoints of the band voxels within half a voxel of
/// it, at most about `limit` of them (every k-th voxel).
std::vector<Eigen::Vector3d> fieldSurfaceSamples(const ApproximantField& field, std::size_t limit) {
  const openvdb::FloatGrid::ConstPtr grid = field.distanceGrid();
  const double h = field.voxelSize();
  std::vector<Eigen::Vector3d> centers;
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    if (std::abs(*it) > 0.5 * h) continue;
    const openvdb::Vec3d p = grid->indexToWorld(it.getCoord());
    centers.emplace_back(p.x(), p.y(), p.z());
  }
  const std::size_t stride = std::max<std::size_t>(1, centers.size() / limit);
  std::vector<Eigen::Vector3d> samples;
  for (std::size_t i = 0; i < centers.size(); i += stride) {
    samples.push_back(field.approximantAt(centers[i]).footpoint);
  }
  return samples;
}

LoadedInput loadTargetFile(const std::filesystem::path& path, const FitTargetOptions& options) {
  LoadOptions load;
  load.purpose = options.purpose;
  load.progress = options.progress;
  if (options.spline == FitSpline::Curve) {
    return loadInput(
        path, {InputKind::Curve, InputKind::Polylines, InputKind::PointSet, InputKind::Field},
        load);
  }
  return loadInput(
      path, {InputKind::Field, InputKind::Surface, InputKind::PointSet, InputKind::Mesh}, load);
}

void takeCurve(LoadedInput input, const std::filesystem::path& path, FitTarget& loaded) {
  std::unique_ptr<CurveTarget> curve;
  if (input.kind() == InputKind::Curve) {
    const BSplineCurve spline = std::move(input).take<BSplineCurve>();
    loaded.pieces = static_cast<std::size_t>(spline.controlPointCount());
    loaded.closed = spline.isClosed();
    loaded.dimension = spline.dimension();
    curve = std::make_unique<CurveTarget>(spline);
  } else {
    Polyline polyline = onlyPolyline(std::move(input).take<PolylinesInput>().polylines, path);
    loaded.pieces = polyline.points.size();
    loaded.closed = polyline.closed;
    loaded.dimension = polyline.dimension;
    curve = std::make_unique<CurveTarget>(std::move(polyline));
  }
  curve->setLabel(path.string());
  loaded.points = curve->samplePoints(curve->length() * kCurveSampleFraction);
  loaded.target = std::move(curve);
}

// A field target, shared: a surface fit also needs points on its zero level set.
void takeField(std::shared_ptr<const ApproximantField> field, const std::filesystem::path& path,
               FitSpline spline, FitTarget& loaded) {
  if (spline == FitSpline::Surface) {
    if (field->statistics().kind != TargetKind::Surface) {
      throw InputError("target file '" + path.string() +
                       "' is not the field of a surface (a level set); fit-surface fits "
                       "surfaces to level sets, B-spline surfaces and point clouds");
    }
    loaded.points = fieldSurfaceSamples(*field, kFieldSurfaceSamples);
    if (loaded.points.empty()) {
      throw InputError("target file '" + path.string() + "' has no voxels on its zero level set");
    }
  }
  loaded.target = std::move(field);
}

void takeSurface(const BSplineSurface& surface, const std::filesystem::path& path,
                 FitTarget& loaded) {
  auto target = std::make_unique<SurfaceTarget>(surface);
  target->setLabel(path.string());
  loaded.points = target->samplePoints(kSurfaceSamplesPerDirection, kSurfaceSamplesPerDirection);
  loaded.target = std::move(target);
}

// Throws InputError when the offset surface can leave the target's working domain, where the
// target answers nothing: it lies up to |offset| beyond the target's points (on every side for a
// sheet), so their bounding box grown by |offset| must stay inside the domain.
void checkOffsetWithinDomain(double offset, const FitTarget& loaded) {
  if (loaded.points.empty()) return;
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : loaded.points) box.extend(p);
  const Eigen::AlignedBox3d domain = loaded.target->domain();
  const double margin =
      std::min((box.min() - domain.min()).minCoeff(), (domain.max() - box.max()).minCoeff());
  if (std::abs(offset) <= margin) return;
  throw InputError("--offset " + formatNumber(offset, 6) + " reaches beyond the target's working " +
                   "domain, which extends only " + formatNumber(std::max(margin, 0.0), 6) +
                   " beyond the target on its nearest side, so the offset surface could not be "
                   "fitted there; use an offset of at most that size" +
                   (loaded.kind == InputKind::Field
                        ? std::string(" or build the field with a larger --padding")
                        : std::string()));
}

void addOffset(double offset, FitSpline spline, FitTarget& loaded) {
  if (offset == 0.0) return;
  if (spline == FitSpline::Curve) {
    if (!loaded.target || loaded.target->kind() != TargetKind::Curve) {
      throw InputError("--offset needs a curve target (a B-spline or polyline .json), not a " +
                       std::string(inputKindName(loaded.kind)) + " target");
    }
  } else if (!loaded.target) {
    throw InputError("--offset needs a field or B-spline surface target, not a point cloud");
  }
  loaded.offset = std::make_unique<OffsetTarget>(*loaded.target, offset);
  checkOffsetWithinDomain(offset, loaded);
}

}  // namespace

FitTarget fitTargetFromInput(LoadedInput input, const FitTargetOptions& options) {
  const std::filesystem::path path = input.path;
  FitTarget loaded;
  loaded.kind = input.kind();
  switch (input.kind()) {
    case InputKind::Curve:
    case InputKind::Polylines:
      takeCurve(std::move(input), path, loaded);
      break;
    case InputKind::PointSet:
      loaded.points = std::move(input).take<PointSetInput>().points;
      loaded.dimension = std::all_of(loaded.points.begin(), loaded.points.end(),
                                     [](const Eigen::Vector3d& p) { return p.z() == 0.0; })
                             ? 2
                             : 3;
      break;
    case InputKind::Field:
      takeField(std::make_shared<const ApproximantField>(std::move(input).take<FieldInput>().field),
                path, options.spline, loaded);
      break;
    case InputKind::Surface:
      takeSurface(std::move(input).take<BSplineSurface>(), path, loaded);
      break;
    default:
      throw InputError("target file '" + path.string() +
                       "' is a triangle mesh; use a level-set or field .vdb (meshes: d2vdb "
                       "mesh2sdf first), a B-spline surface .json or a point cloud .xyz/.ply");
  }
  addOffset(options.offset, options.spline, loaded);
  return loaded;
}

FitTarget fitTargetFromField(std::shared_ptr<const ApproximantField> field,
                             const std::filesystem::path& label, const FitTargetOptions& options) {
  if (!field) throw InputError("no field to fit to");
  FitTarget loaded;
  loaded.kind = InputKind::Field;
  takeField(std::move(field), label, options.spline, loaded);
  addOffset(options.offset, options.spline, loaded);
  return loaded;
}

BSplineCurve initialCurveForTarget(const FitTarget& target, const std::string& shape, int degree,
                                   int controlPoints, bool closed, double offset) {
  if (shape != "circle" && shape != "ellipse" && shape != "polyline") {
    throw InputError("the initial curve shape must be circle, ellipse or polyline, not '" + shape +
                     "'");
  }
  if (target.points.empty()) {
    throw InputError("a " + std::string(inputKindName(target.kind)) +
                     " target gives no points to place a generated initial curve around; pass "
                     "an initial curve (.json)");
  }
  if (shape == "polyline") {
    return fitPolylineLeastSquares(target.points, closed || target.closed, degree, controlPoints,
                                   target.dimension);
  }
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : target.points) box.extend(p);
  const double extent = std::max(box.sizes().maxCoeff(), 1e-300);
  return initialCurveAround(
      target.points, shape == "circle" ? InitialShape::Circle : InitialShape::Ellipse, degree,
      controlPoints, target.dimension, 1.2 + 2.0 * std::abs(offset) / extent);
}

BSplineSurface initialSurfaceForTarget(const FitTarget& target, const std::string& shape,
                                       SurfaceLayout layout, double offset) {
  InitialSurfaceOptions placement;
  if (shape == "plane") {
    placement.shape = InitialSurfaceShape::Plane;
  } else if (shape == "cylinder") {
    placement.shape = InitialSurfaceShape::Cylinder;
    // Around the axis: u by default, v for a ruled surface (its rulings run along u).
    if (!layout.closedU && !layout.closedV)
      (layout.degreeU == 1 ? layout.closedV : layout.closedU) = true;
  } else if (shape == "torus") {
    placement.shape = InitialSurfaceShape::Torus;
    layout.closedU = layout.closedV = true;
  } else {
    throw InputError("the initial surface shape must be plane, cylinder or torus, not '" + shape +
                     "'");
  }
  placement.layout = layout;
  if (offset != 0.0 && placement.shape != InitialSurfaceShape::Plane) {
    Eigen::AlignedBox3d box;
    for (const Eigen::Vector3d& p : target.points) box.extend(p);
    placement.scale = 1.0 + 2.0 * std::abs(offset) / std::max(box.sizes().maxCoeff(), 1e-300);
  }
  return initialSurfaceAround(target.points, placement);
}

FitTarget loadFitTarget(const std::filesystem::path& path, const FitTargetOptions& options) {
  return fitTargetFromInput(loadTargetFile(path, options), options);
}

}  // namespace d2vdb
