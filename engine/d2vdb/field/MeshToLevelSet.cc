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
#include "d2vdb/field/detail/OpenVdbSetup.h"
#include "d2vdb/mesh/MeshMeasures.h"

namespace d2vdb {

using detail::ensureOpenVdbInitialized;
namespace {

constexpr const char* kStage = "mesh to level set";
constexpr double kMaxIndexCoordinate = 1 << 30;

// Forwards OpenVDB's percentage reports (made from the calling thread) to a ProgressCallback.
// The parameterless checks that worker threads make are answered without locking.
class ProgressInterrupter final : public openvdb::util::NullInterrupter {
 public:
  explicit ProgressInterrupter(const ProgressCallback& progress) : progress_(progress) {}

  bool wasInterrupted(int percent = -1) override {
    if (percent < 0 || !progress_) return false;
    const std::lock_guard<std::mutex> lock(mutex_);
    const double fraction = std::clamp(percent / 100.0, 0.0, 1.0);
    if (fraction > lastFraction_) {
      lastFraction_ = fraction;
      progress_(kStage, fraction);
    }
    return false;
  }

 private:
  const ProgressCallback& progress_;
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

bool hasNegativeValue(const openvdb::FloatGrid& grid) {
  for (auto value = grid.cbeginValueOn(); value; ++value) {
    if (*value < 0.0f) return true;
  }
  return false;
}

}  // namespace

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
  ProgressInterrupter interrupter(progress);
  const float bandWidth = static_cast<float>(options.halfWidth);
  const int flags = options.unsignedDistance ? openvdb::tools::UNSIGNED_DISTANCE_FIELD : 0;
  // Called through the NullInterrupter base so that libopenvdb's pre-built instantiation is used.
  openvdb::util::NullInterrupter& baseInterrupter = interrupter;
  result.grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
      baseInterrupter, adapter, *transform, bandWidth, bandWidth, flags);

  if (options.unsignedDistance) {
    result.grid->setName("unsigned_distance");
    result.grid->setGridClass(openvdb::GRID_UNKNOWN);
    result.grid->insertMeta(kDistanceKindMetadata, openvdb::StringMetadata("unsigned"));
  } else {
    result.grid->setName("surface");
    result.grid->setGridClass(openvdb::GRID_LEVEL_SET);
    result.grid->insertMeta(kDistanceKindMetadata, openvdb::StringMetadata("signed"));
    if (!result.meshReport.closed) {
      result.warnings.push_back(
          "the mesh is not closed (" + joinLines(result.meshReport.problems()) +
          "); the sign comes from OpenVDB's exterior sweep, which bridges holes up to about 3 "
          "voxels across: check the result, or use unsigned distance for open surfaces");
    }
    if (result.grid->activeVoxelCount() > 0 && !hasNegativeValue(*result.grid)) {
      result.warnings.push_back(
          "no voxel of the signed field is inside the mesh: the outside leaked in through holes "
          "wider than the voxels can bridge, or the surface encloses no volume; use a larger "
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
