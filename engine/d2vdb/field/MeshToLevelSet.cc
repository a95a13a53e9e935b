// meshToLevelSet(): validation, voxel budget, OpenVDB's conversion in index space, the exact
// signs and the report.
#include "d2vdb/field/MeshToLevelSet.h"

#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/util/NullInterrupter.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <optional>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/VoxelBudget.h"
#include "d2vdb/field/detail/BandRenormalization.h"
#include "d2vdb/field/detail/BandSigns.h"
#include "d2vdb/field/detail/HoleCrossings.h"
#include "d2vdb/field/detail/InsideOutsideMesh.h"
#include "d2vdb/field/detail/OpenVdbSetup.h"
#include "d2vdb/field/detail/SelfIntersection.h"
#include "d2vdb/field/detail/SignPockets.h"
#include "d2vdb/field/detail/WindingNumber.h"
#include "d2vdb/mesh/MeshMeasures.h"

namespace d2vdb {

using detail::ensureOpenVdbInitialized;
namespace {

constexpr const char* kStage = "mesh to level set";

// Forwards OpenVDB's percentage reports (made from the calling thread) to a ProgressCallback.
// OpenVDB reports percentages seldom (seconds apart on large meshes) but checks for interrupts
// without one often, from worker threads: those checks repeat the last fraction once at least
// kRepeatInterval has passed since the last report, so a callback that throws to stop the work
// (a Python Ctrl-C) is heard promptly. Checks in between cost one atomic load and a clock read.
class ProgressInterrupter final : public openvdb::util::NullInterrupter {
 public:
  /// OpenVDB's percentages become fractions 0..1 of the stage.
  explicit ProgressInterrupter(const ProgressCallback& progress)
      : progress_(progress), lastReport_(now()) {}

  bool wasInterrupted(int percent = -1) override {
    if (!progress_) return false;
    if (percent < 0) {
      if (now() - lastReport_.load(std::memory_order_relaxed) < kRepeatInterval) return false;
      const std::lock_guard<std::mutex> lock(mutex_);
      if (now() - lastReport_.load(std::memory_order_relaxed) < kRepeatInterval) return false;
      lastReport_.store(now(), std::memory_order_relaxed);
      progress_(kStage, lastFraction_);
      return false;
    }
    const std::lock_guard<std::mutex> lock(mutex_);
    const double fraction = std::clamp(percent / 100.0, 0.0, 1.0);
    if (fraction > lastFraction_) {
      lastFraction_ = fraction;
      lastReport_.store(now(), std::memory_order_relaxed);
      progress_(kStage, fraction);
    }
    return false;
  }

 private:
  static constexpr std::int64_t kRepeatInterval = 100'000'000;  // nanoseconds

  static std::int64_t now() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }

  const ProgressCallback& progress_;
  std::mutex mutex_;
  double lastFraction_ = 0.0;
  std::atomic<std::int64_t> lastReport_;
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

/// The mesh in index space, prepared for exact signs before the conversion: repaired winding,
/// caps, winding-number fields and the self-intersection test.
class ExactSigns {
 public:
  ExactSigns(const std::vector<openvdb::Vec3s>& indexPoints,
             const std::vector<openvdb::Vec3I>& triangles)
      : mesh_(prepare(indexPoints, triangles)), closed_(mesh_.points, mesh_.triangles) {
    if (!mesh_.caps.empty()) caps_.emplace(mesh_.points, mesh_.caps);
    // Index coordinates stay below 2^30; 1e-10 of them is far above double rounding.
    double largest = 1.0;
    for (const Eigen::Vector3d& p : mesh_.points) {
      largest = std::max(largest, p.cwiseAbs().maxCoeff());
    }
    report_.reorientedTriangles = mesh_.reorientedTriangles;
    report_.watertight = mesh_.watertight;
    report_.holesClosed = mesh_.capLoops;
    // The pocket rule needs to know which triangles meet others, not only whether some do.
    intersecting_ = detail::selfIntersectingTriangles(
        mesh_.points, mesh_.triangles, mesh_.degenerate, closed_.hierarchy(), 1e-10 * largest);
    report_.selfIntersecting =
        std::find(intersecting_.begin(), intersecting_.end(), true) != intersecting_.end();
    report_.method =
        report_.selfIntersecting ? SignMethod::windingNumber : SignMethod::closestFeature;
    if (!report_.selfIntersecting) {
      sides_ = detail::componentSides(mesh_, closed_);
      for (const detail::ComponentSides& side : sides_) {
        enclosedSurface_ = enclosedSurface_ || side.enclosed;
        if (side.known) ++report_.windingNumberQueries;
      }
    }
  }

  /// meshToVolume flags: renormalisation and trimming wait for the right signs (and the raw
  /// values prove which voxels are far from the mesh). meshToVolume also removes the band of
  /// every surface its exterior sweep cannot reach (meant for surfaces buried in self-
  /// intersecting meshes). That removal is turned off when a surface of an embedded mesh is
  /// enclosed by another (a cavity, a nested shell), which it would delete, and for every mesh
  /// that intersects itself: there the voxels beside a removed wall keep a closest triangle that
  /// is not their closest, so their clearances would link voxels across the wall and carry one
  /// winding number to both sides (on the Stanford dragon's res2 scan, most of the body came out
  /// as outside). The band's interior beyond a voxel from the surface is then less accurate
  /// (OpenVDB no longer recomputes the voxels it would have removed).
  int conversionFlags() const {
    return openvdb::tools::DISABLE_RENORMALIZATION | openvdb::tools::DISABLE_NARROW_BAND_TRIMMING |
           (enclosedSurface_ || report_.selfIntersecting
                ? openvdb::tools::DISABLE_INTERSECTING_VOXEL_REMOVAL
                : 0);
  }

  /// The progress stage of correct(), which names the method.
  std::string stage() const {
    return std::string("exact signs (") + signMethodName(report_.method) + ")";
  }

  /// Corrects the signs of the converted band (see correctBandSigns()); reports stage() to
  /// `progress` from its start.
  SignReport correct(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closestTriangles,
                     const ProgressCallback& progress) {
    const std::string name = stage();
    if (progress) progress(name, 0.0);
    detail::BandSignInputs inputs;
    if (progress) inputs.progress = [&](double fraction) { progress(name, fraction); };
    inputs.mesh = &mesh_;
    inputs.closed = &closed_;
    inputs.caps = caps_ ? &*caps_ : nullptr;
    inputs.embedded = !report_.selfIntersecting;
    inputs.sides = &sides_;
    const detail::BandSignReport band = detail::correctBandSigns(grid, closestTriangles, inputs);
    SignReport report = report_;
    report.correctedVoxels = band.correctedVoxels;
    report.windingNumberQueries += band.windingNumberQueries + band.capQueries;
    if (progress) progress(name, 1.0);
    return report;
  }

  /// After the band's renormalisation and trimming: activates the voxels beside the surfaces
  /// that close the holes where they leave the band (coverHoleCrossings()), then fills the
  /// pockets that only open or non-manifold parts bound (fillSignPockets(); after the closing
  /// voxels, which enclose the pockets that reach beyond the band), and counts both in `report`.
  void finish(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closestTriangles,
              SignReport& report) const {
    if (caps_) {
      const detail::HoleCrossingReport holes =
          detail::coverHoleCrossings(grid, mesh_, closed_, *caps_);
      report.holeVoxels = holes.addedVoxels;
      report.windingNumberQueries += holes.windingNumberQueries;
    }
    const detail::SignPocketReport pockets =
        detail::fillSignPockets(grid, closestTriangles, mesh_, intersecting_);
    report.pocketsFilled = pockets.pockets;
    report.pocketVoxels = pockets.voxels;
  }

 private:
  static detail::InsideOutsideMesh prepare(const std::vector<openvdb::Vec3s>& indexPoints,
                                           const std::vector<openvdb::Vec3I>& triangles) {
    std::vector<Eigen::Vector3d> points(indexPoints.size());
    for (std::size_t i = 0; i < indexPoints.size(); ++i) {
      points[i] = Eigen::Vector3d(indexPoints[i].x(), indexPoints[i].y(), indexPoints[i].z());
    }
    std::vector<TriangleIndices> corners(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      corners[i] = {triangles[i].x(), triangles[i].y(), triangles[i].z()};
    }
    return detail::prepareInsideOutsideMesh(std::move(points), corners);
  }

  detail::InsideOutsideMesh mesh_;
  detail::WindingNumberField closed_;
  std::optional<detail::WindingNumberField> caps_;
  std::vector<detail::ComponentSides> sides_;
  std::vector<bool> intersecting_;  ///< per triangle of mesh_: meets another one
  bool enclosedSurface_ = false;
  SignReport report_;
};

/// Whether some value is inside by more than rounding (voxel centres on the surface may carry
/// either sign).
bool hasInsideValue(const openvdb::FloatGrid& grid) {
  const float margin = static_cast<float>(-1e-5 * grid.voxelSize()[0]);
  for (auto value = grid.cbeginValueOn(); value; ++value) {
    if (*value < margin) return true;
  }
  return false;
}

/// The voxel size (world units) the options ask for, after checking that the mesh has extent,
/// that the band fits the voxel budget and that the mesh stays inside OpenVDB's index range.
double checkedVoxelSize(const TriangleMesh& mesh, const LevelSetOptions& options) {
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
  budget.boxSides = {bounds.extent().x(), bounds.extent().y(), bounds.extent().z()};
  budget.pieces = surfacePieces(mesh);
  budget.voxelSize = voxelSize;
  budget.halfWidth = options.halfWidth;
  budget.longestSide = longestSide;
  budget.maxActiveVoxels = options.maxActiveVoxels;
  budget.bytesPerVoxel = kLevelSetPeakBytesPerVoxel + options.extraBytesPerVoxel;
  budget.fixedBytes = kLevelSetBytesPerTriangle * static_cast<double>(mesh.triangles.size());
  budget.maxMemoryBytes = options.maxMemoryBytes;
  enforceVoxelBudget(budget);

  const double reach = std::max(bounds.min.cwiseAbs().maxCoeff(), bounds.max.cwiseAbs().maxCoeff());
  if (!(reach / voxelSize + options.halfWidth < kMaxIndexCoordinate)) {
    std::ostringstream message;
    message << "mesh to level set: at voxel size " << voxelSize << " the mesh reaches index "
            << "coordinate " << reach / voxelSize << ", beyond OpenVDB's range of +-2^30; use a "
            << "larger voxel size or move the mesh closer to the origin";
    throw InputError(message.str());
  }
  return voxelSize;
}

/// The mesh as OpenVDB's conversion takes it: vertices in index space, corner indices.
struct IndexSpaceMesh {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
};

IndexSpaceMesh toIndexSpace(const TriangleMesh& mesh, const openvdb::math::Transform& transform) {
  IndexSpaceMesh result;
  std::vector<openvdb::Vec3s>& indexPoints = result.points;
  indexPoints.resize(mesh.positions.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.positions.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const Eigen::Vector3f& p = mesh.positions[i];
                        indexPoints[i] = openvdb::Vec3s(transform.worldToIndex(
                            openvdb::Vec3d(double(p.x()), double(p.y()), double(p.z()))));
                      }
                    });
  result.triangles.resize(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const TriangleMesh::Triangle& t = mesh.triangles[i];
    result.triangles[i] = openvdb::Vec3I(t[0], t[1], t[2]);
  }
  return result;
}

/// The warnings about how the signs of a signed level set were decided (result.signs, from
/// exact signs or, without them, OpenVDB's sweep) and whether the field has an inside at all.
void addSignWarnings(const TriangleMesh& mesh, bool exactSigns, LevelSetResult& result) {
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
        "); inside is where its generalised winding number is at least 1/2, which closes its " +
        std::to_string(signs.holesClosed) +
        " holes smoothly: check the result, or use unsigned distance for open surfaces");
  }
  if (signs.selfIntersecting) {
    result.warnings.push_back(
        std::string("the mesh ") + (signs.watertight ? "" : "(with its holes closed) ") +
        "intersects or touches itself; inside is where its winding number is at least 1/2 "
        "(the union of overlapping parts), evaluated at every voxel near the surface (slower)");
  }
  if (signs.reorientedTriangles > 0) {
    result.warnings.push_back(
        std::to_string(signs.reorientedTriangles) + " of " + std::to_string(mesh.triangles.size()) +
        " triangles were wound against their neighbours (or the mesh inside out) and were "
        "reversed for the inside/outside decision");
  }
  if (result.grid->activeVoxelCount() > 0 && !hasInsideValue(*result.grid)) {
    result.warnings.push_back(
        "no voxel of the signed field is inside the mesh: the surface encloses no volume (a "
        "sheet or a shell with large holes), or the voxels are too coarse for it; use a smaller "
        "voxel size, repair the mesh, or use unsigned distance");
  }
}

}  // namespace

const char* signMethodName(SignMethod method) {
  switch (method) {
    case SignMethod::closestFeature:
      return "closest feature";
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
  const double voxelSize = checkedVoxelSize(mesh, options);

  ensureOpenVdbInitialized();
  if (progress) progress(kStage, 0.0);

  const openvdb::math::Transform::Ptr transform =
      openvdb::math::Transform::createLinearTransform(voxelSize);
  const IndexSpaceMesh indexMesh = toIndexSpace(mesh, *transform);
  const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(
      indexMesh.points, indexMesh.triangles);
  const float bandWidth = static_cast<float>(options.halfWidth);
  const bool exactSigns = !options.unsignedDistance && options.exactSigns;
  std::optional<ExactSigns> signs;
  if (exactSigns) signs.emplace(indexMesh.points, indexMesh.triangles);
  ProgressInterrupter interrupter(progress);
  const int flags = options.unsignedDistance ? openvdb::tools::UNSIGNED_DISTANCE_FIELD
                                             : (signs ? signs->conversionFlags() : 0);
  // Called through the NullInterrupter base so that libopenvdb's pre-built instantiation is used.
  openvdb::util::NullInterrupter& baseInterrupter = interrupter;
  openvdb::Int32Grid closestTriangles;
  result.grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
      baseInterrupter, adapter, *transform, bandWidth, bandWidth, flags,
      signs ? &closestTriangles : nullptr);

  if (options.unsignedDistance) {
    result.grid->setName("unsigned_distance");
    result.grid->setGridClass(openvdb::GRID_UNKNOWN);
    result.grid->insertMeta(kDistanceKindMetadata, openvdb::StringMetadata("unsigned"));
  } else {
    result.grid->setName("surface");
    result.grid->setGridClass(openvdb::GRID_LEVEL_SET);
    result.grid->insertMeta(kDistanceKindMetadata, openvdb::StringMetadata("signed"));
    if (signs) {
      if (progress) progress(kStage, 1.0);
      result.signs = signs->correct(*result.grid, closestTriangles, progress);
      detail::renormalizeBand(*result.grid);
      if (bandWidth < 4.0f) detail::trimBand(*result.grid);
      signs->finish(*result.grid, closestTriangles, result.signs);
    }
    addSignWarnings(mesh, exactSigns, result);
  }
  if (result.meshReport.closed && !result.meshReport.problems().empty()) {
    result.warnings.push_back("mesh problems that do not affect the distance field: " +
                              joinLines(result.meshReport.problems()));
  }
  if (progress && !signs) progress(kStage, 1.0);
  return result;
}

}  // namespace d2vdb
