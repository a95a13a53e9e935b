#include "d2vdb/field/MeshToLevelSet.h"

#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/util/NullInterrupter.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/detail/BandSigns.h"
#include "d2vdb/field/detail/InsideOutsideMesh.h"
#include "d2vdb/field/detail/OpenVdbSetup.h"
#include "d2vdb/field/detail/SelfIntersection.h"
#include "d2vdb/field/detail/WindingNumber.h"
#include "d2vdb/mesh/MeshMeasures.h"

namespace d2vdb {

using detail::ensureOpenVdbInitialized;
namespace {

constexpr const char* kStage = "mesh to level set";
/// Share of the progress stage given to OpenVDB's conversion when the signs are checked after it.
constexpr double kConversionShare = 0.9;
constexpr double kMaxIndexCoordinate = 1 << 30;

// Forwards OpenVDB's percentage reports (made from the calling thread) to a ProgressCallback.
// The parameterless checks that worker threads make are answered without locking.
class ProgressInterrupter final : public openvdb::util::NullInterrupter {
 public:
  /// OpenVDB's percentages become fractions 0..`share` of the stage.
  ProgressInterrupter(const ProgressCallback& progress, double share)
      : progress_(progress), share_(share) {}

  bool wasInterrupted(int percent = -1) override {
    if (percent < 0 || !progress_) return false;
    const std::lock_guard<std::mutex> lock(mutex_);
    const double fraction = share_ * std::clamp(percent / 100.0, 0.0, 1.0);
    if (fraction > lastFraction_) {
      lastFraction_ = fraction;
      progress_(kStage, fraction);
    }
    return false;
  }

 private:
  const ProgressCallback& progress_;
  const double share_;
  std::mutex mutex_;
  double lastFraction_ = 0.0;
};

std::string joinLines(const std::string& text) {
  std::string joined;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    if (!joined.empty()) joined += "; ";
    joined += line;
  }
  return joined;
}

void validateOptions(const LevelSetOptions& options) {
  if (std::isnan(options.voxelSize) || options.voxelSize < 0.0 || std::isinf(options.voxelSize)) {
    std::ostringstream message;
    message << "mesh to level set: the voxel size must be a finite positive number of world "
            << "units (or 0 to use the resolution), got " << options.voxelSize;
    throw InputError(message.str());
  }
  if (options.voxelSize == 0.0 && options.resolution <= 0) {
    throw InputError(
        "mesh to level set: give a positive voxel size or a positive resolution "
        "(voxels along the longest side of the bounding box); got resolution " +
        std::to_string(options.resolution));
  }
  if (!std::isfinite(options.halfWidth) || !(options.halfWidth >= 1.0)) {
    std::ostringstream message;
    message << "mesh to level set: the narrow-band half-width must be at least 1 voxel, got "
            << options.halfWidth;
    throw InputError(message.str());
  }
}

void validateGeometry(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) {
    throw InputError("mesh to level set: the mesh has no triangles (" +
                     std::to_string(mesh.positions.size()) + " vertices); nothing to convert");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!mesh.positions[i].allFinite()) {
      std::ostringstream message;
      message << "mesh to level set: vertex " << i << " has a non-finite coordinate ("
              << mesh.positions[i].x() << ", " << mesh.positions[i].y() << ", "
              << mesh.positions[i].z() << "); repair or remove it";
      throw InputError(message.str());
    }
  }
}

/// Decides every band voxel's side exactly and corrects the grid (see correctBandSigns()).
SignReport correctSigns(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closestTriangles,
                        const std::vector<openvdb::Vec3s>& indexPoints,
                        const std::vector<openvdb::Vec3I>& triangles) {
  std::vector<Eigen::Vector3d> points(indexPoints.size());
  for (std::size_t i = 0; i < indexPoints.size(); ++i) {
    points[i] = Eigen::Vector3d(indexPoints[i].x(), indexPoints[i].y(), indexPoints[i].z());
  }
  std::vector<detail::TriangleIndices> corners(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    corners[i] = {triangles[i].x(), triangles[i].y(), triangles[i].z()};
  }
  const detail::InsideOutsideMesh mesh =
      detail::prepareInsideOutsideMesh(std::move(points), corners);
  const detail::WindingNumberField winding(mesh.points, mesh.triangles);
  SignReport report;
  report.reorientedTriangles = mesh.reorientedTriangles;
  report.watertight = mesh.watertight;
  detail::BandSignMode mode = detail::BandSignMode::windingNumberEveryVoxel;
  report.method = SignMethod::windingNumber;
  if (mesh.watertight) {
    // Index coordinates are below 2^30; rounding in the tests stays far below this.
    double largest = 1.0;
    for (const Eigen::Vector3d& p : mesh.points)
      largest = std::max(largest, p.cwiseAbs().maxCoeff());
    report.selfIntersecting = detail::hasSelfIntersection(
        mesh.points, mesh.triangles, mesh.degenerate, winding.hierarchy(), 1e-10 * largest);
    mode = report.selfIntersecting ? detail::BandSignMode::windingNumberNearSurface
                                   : detail::BandSignMode::closestFeature;
    report.method =
        report.selfIntersecting ? SignMethod::windingNumberNearSurface : SignMethod::closestFeature;
  }
  const detail::BandSignReport band =
      detail::correctBandSigns(grid, closestTriangles, mesh, winding, mode);
  report.correctedVoxels = band.correctedVoxels;
  report.windingNumberQueries = band.windingNumberQueries;
  return report;
}

bool hasNegativeValue(const openvdb::FloatGrid& grid) {
  for (auto value = grid.cbeginValueOn(); value; ++value) {
    if (*value < 0.0f) return true;
  }
  return false;
}

}  // namespace

const char* signMethodName(SignMethod method) {
  switch (method) {
    case SignMethod::closestFeature:
      return "closest feature";
    case SignMethod::windingNumberNearSurface:
      return "winding number near surface";
    case SignMethod::windingNumber:
      return "winding number";
    case SignMethod::none:
      break;
  }
  return "none";
}

LevelSetResult meshToLevelSet(const TriangleMesh& mesh, const LevelSetOptions& options,
                              const ProgressCallback& progress) {
  validateOptions(options);
  validateGeometry(mesh);
  LevelSetResult result;
  result.meshReport = validateMesh(mesh);  // throws InputError for out-of-range indices

  const BoundingBox bounds = boundingBox(mesh);
  const double longestSide = bounds.extent().maxCoeff();
  if (!(longestSide > 0.0)) {
    throw InputError("mesh to level set: all " + std::to_string(mesh.positions.size()) +
                     " vertices coincide (the bounding box has zero extent); nothing to convert");
  }
  const double voxelSize =
      options.voxelSize > 0.0 ? options.voxelSize : longestSide / options.resolution;

  VoxelBudgetRequest budget;
  budget.subject =
      "the level set of a mesh of " + std::to_string(mesh.triangles.size()) + " triangles";
  budget.surfaceArea = surfaceArea(mesh);
  budget.voxelSize = voxelSize;
  budget.halfWidth = options.halfWidth;
  budget.longestSide = longestSide;
  budget.maxActiveVoxels = options.maxActiveVoxels;
  enforceVoxelBudget(budget);

  const double reach = std::max(bounds.min.cwiseAbs().maxCoeff(), bounds.max.cwiseAbs().maxCoeff());
  if (!(reach / voxelSize + options.halfWidth < kMaxIndexCoordinate)) {
    std::ostringstream message;
    message << "mesh to level set: at voxel size " << voxelSize << " the mesh reaches index "
            << "coordinate " << reach / voxelSize << ", beyond OpenVDB's range of +-2^30; use a "
            << "larger voxel size or move the mesh closer to the origin";
    throw InputError(message.str());
  }

  ensureOpenVdbInitialized();
  if (progress) progress(kStage, 0.0);

  const openvdb::math::Transform::Ptr transform =
      openvdb::math::Transform::createLinearTransform(voxelSize);
  std::vector<openvdb::Vec3s> indexPoints(mesh.positions.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.positions.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const Eigen::Vector3f& p = mesh.positions[i];
                        indexPoints[i] = openvdb::Vec3s(transform->worldToIndex(
                            openvdb::Vec3d(double(p.x()), double(p.y()), double(p.z()))));
                      }
                    });
  std::vector<openvdb::Vec3I> triangles(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const TriangleMesh::Triangle& t = mesh.triangles[i];
    triangles[i] = openvdb::Vec3I(t[0], t[1], t[2]);
  }

  const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(
      indexPoints, triangles);
  const bool exactSigns = !options.unsignedDistance && options.exactSigns;
  ProgressInterrupter interrupter(progress, exactSigns ? kConversionShare : 1.0);
  const float bandWidth = static_cast<float>(options.halfWidth);
  const int flags = options.unsignedDistance ? openvdb::tools::UNSIGNED_DISTANCE_FIELD : 0;
  // Called through the NullInterrupter base so that libopenvdb's pre-built instantiation is used.
  openvdb::util::NullInterrupter& baseInterrupter = interrupter;
  openvdb::Int32Grid closestTriangles;
  result.grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
      baseInterrupter, adapter, *transform, bandWidth, bandWidth, flags,
      exactSigns ? &closestTriangles : nullptr);

  if (options.unsignedDistance) {
    result.grid->setName("unsigned_distance");
    result.grid->setGridClass(openvdb::GRID_UNKNOWN);
    result.grid->insertMeta(kDistanceKindMetadata, openvdb::StringMetadata("unsigned"));
  } else {
    result.grid->setName("surface");
    result.grid->setGridClass(openvdb::GRID_LEVEL_SET);
    result.grid->insertMeta(kDistanceKindMetadata, openvdb::StringMetadata("signed"));
    if (exactSigns) {
      result.signs = correctSigns(*result.grid, closestTriangles, indexPoints, triangles);
    }
    const SignReport& signs = result.signs;
    if (!exactSigns && !result.meshReport.closed) {
      result.warnings.push_back(
          "the mesh is not closed (" + joinLines(result.meshReport.problems()) +
          "); the sign comes from OpenVDB's exterior sweep, which bridges holes up to about 3 "
          "voxels across: check the result, or use unsigned distance for open surfaces");
    }
    if (exactSigns && !signs.watertight) {
      result.warnings.push_back(
          "the mesh is not closed (" + joinLines(result.meshReport.problems()) +
          "); inside is where its generalised winding number is at least 1/2, which closes "
          "holes smoothly (every band voxel evaluated: slower): check the result, or use "
          "unsigned distance for open surfaces");
    }
    if (signs.selfIntersecting) {
      result.warnings.push_back(
          "the mesh intersects itself; inside is where its winding number is at least 1/2 (the "
          "union of overlapping parts), evaluated at every voxel near the surface (slower)");
    }
    if (signs.reorientedTriangles > 0) {
      result.warnings.push_back(
          std::to_string(signs.reorientedTriangles) + " of " +
          std::to_string(mesh.triangles.size()) +
          " triangles were wound against their neighbours (or the mesh inside out) and were "
          "reversed for the inside/outside decision");
    }
    if (signs.correctedVoxels > 0) {
      result.warnings.push_back(
          std::to_string(signs.correctedVoxels) +
          " band voxels had the wrong sign from OpenVDB's mesh conversion and were corrected (" +
          signMethodName(signs.method) + ")");
    }
    if (result.grid->activeVoxelCount() > 0 && !hasNegativeValue(*result.grid)) {
      result.warnings.push_back(
          "no voxel of the signed field is inside the mesh: the surface encloses no volume (a "
          "sheet or a shell with large holes), or the voxels are too coarse for it; use a smaller "
          "voxel size, repair the mesh, or use unsigned distance");
    }
  }
  if (result.meshReport.closed && !result.meshReport.problems().empty()) {
    result.warnings.push_back("mesh problems that do not affect the distance field: " +
                              joinLines(result.meshReport.problems()));
  }
  if (progress) progress(kStage, 1.0);
  return result;
}

}  // namespace d2vdb
