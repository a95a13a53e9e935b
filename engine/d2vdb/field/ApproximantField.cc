// The squared-distance approximant field: construction, queries, statistics and conversion to
// and from standard OpenVDB grids (ApproximantField.h).
#include "d2vdb/field/ApproximantField.h"

#include <openvdb/tools/Morphology.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <nanoflann.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/field/detail/FieldStorage.h"
#include "d2vdb/field/detail/OpenVdbSetup.h"
#include "d2vdb/field/detail/SurfaceEstimator.h"

namespace d2vdb {

using detail::BandRecord;
using detail::CoarseLevel;
using detail::ensureOpenVdbInitialized;
using detail::estimateSurfaceRecords;
using detail::FieldStorage;
using detail::kSurfaceEstimator;
using detail::LeafEntry;
using detail::LeafTable;
using detail::nearestInt;
using detail::tangentBasis;
namespace {

constexpr int kFieldFormatVersion = 1;
constexpr const char* kCurveEstimator =
    "exact nearest point of the curve at every voxel centre (B-spline: Bezier root isolation; "
    "polyline: nearest segment, curvature from vertex circles)";
constexpr const char* kPointsEstimator = "exact nearest point (k-d tree) at every voxel centre";

std::string formatNumber(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

std::string formatPoint(const Eigen::Vector3d& p) {
  return "(" + formatNumber(p.x()) + ", " + formatNumber(p.y()) + ", " + formatNumber(p.z()) + ")";
}

openvdb::Coord roundToCoord(const Eigen::Vector3d& p) {
  return openvdb::Coord(nearestInt(p.x()), nearestInt(p.y()), nearestInt(p.z()));
}

void checkBandParameters(double voxelSize, double halfWidth, const char* what) {
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize)) {
    throw InputError(std::string(what) + ": the voxel size must be a positive finite number, not " +
                     formatNumber(voxelSize));
  }
  if (!(halfWidth >= 1.0) || !std::isfinite(halfWidth) || halfWidth > 64.0) {
    throw InputError(std::string(what) +
                     ": the band half-width must be between 1 and 64 voxels, "
                     "not " +
                     formatNumber(halfWidth));
  }
}

void checkBudget(double estimate, std::uint64_t limit, const std::string& what) {
  if (estimate > static_cast<double>(limit)) {
    throw InputError(what + " would need about " + formatNumber(estimate) +
                     " active voxels, above the limit of " + std::to_string(limit) +
                     "; use a larger voxel size or a narrower band");
  }
}

/// Builds the band of an unsigned field from candidate voxels (a mask) and a per-voxel
/// approximant function (world centre -> index-frame approximant with world distance).
template <typename Compute>
void buildUnsignedBand(FieldStorage& storage, openvdb::MaskGrid& candidates, double halfWidth,
                       const Compute& compute, const ProgressCallback& progress) {
  const double h = storage.voxelSize;
  const double limit = halfWidth * h;
  std::vector<const openvdb::MaskGrid::TreeType::LeafNodeType*> leaves;
  for (auto leaf = candidates.tree().cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf.getLeaf());
  struct Kept {
    std::vector<int> offsets;
    std::vector<Approximant> approximants;
  };
  std::vector<Kept> kept(leaves.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 4),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        for (auto voxel = leaves[i]->cbeginValueOn(); voxel; ++voxel) {
                          const openvdb::Coord ijk = voxel.getCoord();
                          const Eigen::Vector3d centre =
                              storage.indexToWorld(Eigen::Vector3d(ijk.x(), ijk.y(), ijk.z()));
                          Approximant a = compute(centre);
                          if (!(a.distance < limit)) continue;
                          kept[i].offsets.push_back(static_cast<int>(voxel.pos()));
                          kept[i].approximants.push_back(std::move(a));
                        }
                      }
                    });
  if (progress) progress("field: approximants", 0.8);
  // The distance grid, leaf by leaf in candidate order.
  auto grid = openvdb::FloatGrid::create(static_cast<float>(limit));
  grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
  grid->setGridClass(openvdb::GRID_UNKNOWN);
  grid->setName("unsigned_distance");
  {
    auto accessor = grid->getAccessor();
    for (std::size_t i = 0; i < leaves.size(); ++i) {
      const openvdb::Coord origin = leaves[i]->origin();
      for (std::size_t k = 0; k < kept[i].offsets.size(); ++k) {
        const int offset = kept[i].offsets[k];
        accessor.setValueOn(origin + openvdb::Coord(offset >> 6, (offset >> 3) & 7, offset & 7),
                            static_cast<float>(kept[i].approximants[k].distance));
      }
    }
  }
  if (grid->activeVoxelCount() == 0) {
    throw InputError("the target has no voxel within the band at this voxel size");
  }
  storage.grid = grid;
  const auto bandLeaves = storage.buildBandTable();
  std::unordered_map<openvdb::Coord, std::size_t> candidateOf;
  for (std::size_t i = 0; i < leaves.size(); ++i) candidateOf.emplace(leaves[i]->origin(), i);
  const auto& entries = storage.band.entries();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, entries.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const Kept& source = kept[candidateOf.at(entries[i].origin)];
                        for (std::size_t k = 0; k < source.approximants.size(); ++k) {
                          storage.records[entries[i].base + k] =
                              storage.encode(source.approximants[k]);
                        }
                      }
                    });
}

/// Activates the voxels containing `points` (index space: world / h) and dilates by `radius`.
openvdb::MaskGrid::Ptr candidateMask(const std::vector<Eigen::Vector3d>& worldPoints,
                                     const FieldStorage& storage, int radius) {
  auto mask = openvdb::MaskGrid::create(false);
  auto accessor = mask->getAccessor();
  for (const Eigen::Vector3d& p : worldPoints) {
    accessor.setValueOn(roundToCoord(storage.worldToIndex(p)));
  }
  openvdb::tools::dilateActiveValues(mask->tree(), radius, openvdb::tools::NN_FACE_EDGE_VERTEX,
                                     openvdb::tools::IGNORE_TILES);
  return mask;
}

/// nanoflann adaptor over input points (double).
struct PointCloud {
  const std::vector<Eigen::Vector3d>* points;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(std::size_t index, std::size_t dim) const { return (*points)[index][dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

/// A unit vector orthogonal to `v`, deterministic.
Eigen::Vector3d orthogonalTo(const Eigen::Vector3d& v) {
  const Eigen::Vector3d axis =
      std::abs(v.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return axis.cross(v).normalized();
}

/// Moves an approximant taken at a voxel centre to the nearby query point x (world), to first
/// order in x - origin: the distance changes by the normal component, the footpoint slides by the
/// tangential components divided by 1 + d k_i, and the normal turns with it; curvatures stay.
/// This makes the Hessian of the SDM form the one at x rather than at the voxel centre.
void transportTo(Approximant& a, const Eigen::Vector3d& x) {
  const Eigen::Vector3d delta = x - a.origin;
  a.origin = x;
  if (a.kind == TargetKind::Points || (a.kind == TargetKind::Curve && (a.flags & kFlagEndPoint))) {
    const Eigen::Vector3d offset = x - a.footpoint;
    a.distance = offset.norm();
    if (a.distance > 0.0) a.normal = offset / a.distance;
    Eigen::Vector3d t = a.tangent - a.tangent.dot(a.normal) * a.normal;
    a.tangent = t.norm() > 1e-9 ? Eigen::Vector3d(t.normalized()) : orthogonalTo(a.normal);
    return;
  }
  if (a.kind == TargetKind::Curve) {
    const double focal = 1.0 + a.distance * a.tangentCurvature();
    if (focal > 0.05) a.footpoint += delta.dot(a.tangent) / focal * a.tangent;
    const Eigen::Vector3d offset = x - a.footpoint;
    a.distance = offset.norm();
    if (a.distance > 1e-12 * std::max(1.0, x.cwiseAbs().maxCoeff())) {
      a.normal = offset / a.distance;
      Eigen::Vector3d t = a.tangent - a.tangent.dot(a.normal) * a.normal;
      a.tangent = t.norm() > 1e-9 ? Eigen::Vector3d(t.normalized()) : orthogonalTo(a.normal);
    }
    if (a.k1 > 0.0) {
      Eigen::Vector3d n = a.principalNormal - a.principalNormal.dot(a.tangent) * a.tangent;
      a.principalNormal =
          n.norm() > 1e-9 ? Eigen::Vector3d(n.normalized()) : orthogonalTo(a.tangent);
    }
    return;
  }
  const Eigen::Vector3d e2 = a.bitangent();
  const double t1 = delta.dot(a.tangent), t2 = delta.dot(e2);
  const double f1 = 1.0 + a.distance * a.k1, f2 = 1.0 + a.distance * a.k2;
  if ((a.flags & kFlagCutLocus) == 0 && f1 > 0.05 && f2 > 0.05) {
    a.footpoint += t1 / f1 * a.tangent + t2 / f2 * e2;
    const Eigen::Vector3d normal =
        (a.normal + a.k1 * t1 / f1 * a.tangent + a.k2 * t2 / f2 * e2).normalized();
    Eigen::Vector3d e1 = a.tangent - a.tangent.dot(normal) * normal;
    a.tangent = e1.norm() > 1e-9 ? Eigen::Vector3d(e1.normalized()) : orthogonalTo(normal);
    a.normal = normal;
    a.distance = (x - a.footpoint).dot(a.normal);
  } else {
    a.distance += delta.dot(a.normal);
    a.footpoint = x - a.distance * a.normal;
  }
}

void countFlags(const std::vector<BandRecord>& records, FieldStatistics& stats) {
  for (const BandRecord& record : records) {
    if (record.flags & kFlagCutLocus) ++stats.flaggedCutLocus;
    if (record.flags & kFlagCurvatureClamped) ++stats.flaggedCurvatureClamped;
    if (record.flags & kFlagDegradedEstimate) ++stats.flaggedDegraded;
  }
}

void setFieldMetadata(openvdb::GridBase& grid, const FieldStorage& storage) {
  grid.insertMeta(kFieldKindMetadata, openvdb::StringMetadata(targetKindName(storage.kind)));
  grid.insertMeta(kFieldEstimatorMetadata, openvdb::StringMetadata(storage.estimator));
  grid.insertMeta(kFieldVersionMetadata, openvdb::Int32Metadata(kFieldFormatVersion));
  const auto toVec = [](const Eigen::Vector3d& v) { return openvdb::Vec3d(v.x(), v.y(), v.z()); };
  grid.insertMeta(kFieldDomainMinMetadata, openvdb::Vec3DMetadata(toVec(storage.domain.min())));
  grid.insertMeta(kFieldDomainMaxMetadata, openvdb::Vec3DMetadata(toVec(storage.domain.max())));
}

}  // namespace

// ---- construction ------------------------------------------------------------------------------

ApproximantField::ApproximantField(std::unique_ptr<FieldStorage> storage)
    : storage_(std::move(storage)) {}
ApproximantField::ApproximantField(ApproximantField&&) noexcept = default;
ApproximantField& ApproximantField::operator=(ApproximantField&&) noexcept = default;
ApproximantField::~ApproximantField() = default;

ApproximantField ApproximantField::fromLevelSet(openvdb::FloatGrid::ConstPtr levelSet,
                                                const ApproximantFieldOptions& options,
                                                const ProgressCallback& progress) {
  ensureOpenVdbInitialized();
  if (!levelSet) throw InputError("approximant field: no level set given");
  const std::string source = "level set '" + levelSet->getName() + "'";
  if (levelSet->getGridClass() == openvdb::GRID_FOG_VOLUME ||
      levelSet->getGridClass() == openvdb::GRID_STAGGERED) {
    throw InputError(source + " is a fog volume or staggered grid, not a signed distance field");
  }
  auto storage = std::make_unique<FieldStorage>();
  storage->kind = TargetKind::Surface;
  storage->coarseHalfWidth = std::max(2, options.coarseHalfWidth);
  storage->setTransform(levelSet->transform(), source);
  const std::uint64_t active = levelSet->activeVoxelCount();
  if (active == 0) throw InputError(source + " has no active voxels (an empty band)");
  storage->halfWidth = std::abs(static_cast<double>(levelSet->background())) / storage->voxelSize;
  if (!(storage->halfWidth >= 2.0 - 1e-6)) {
    throw InputError(source + " has a band half-width of " + formatNumber(storage->halfWidth) +
                     " voxels (background / voxel size); the curvature estimator needs at least 2;"
                     " rebuild it with --half-width 3");
  }
  checkBudget(1.4 * static_cast<double>(active), options.maxActiveVoxels,
              "the approximant field of " + source);
  if (levelSet->tree().hasActiveTiles()) {
    auto voxelized = levelSet->deepCopy();
    voxelized->tree().voxelizeActiveTiles();
    levelSet = voxelized;
  }
  storage->grid = levelSet;
  storage->estimator = kSurfaceEstimator;
  storage->label = source;
  const auto leaves = storage->buildBandTable();
  if (progress) progress("field: approximants", 0.0);
  estimateSurfaceRecords(*storage, leaves, progress);
  {
    // The distance grid holds the distances the footpoints imply (the input's values corrected by
    // the projection onto the zero level), so grid, records and files agree.
    auto refined = levelSet->deepCopy();
    std::vector<openvdb::FloatTree::LeafNodeType*> refinedLeaves;
    refinedLeaves.reserve(leaves.size());
    for (auto leaf = refined->tree().beginLeaf(); leaf; ++leaf) {
      if (!leaf->getValueMask().isOff()) refinedLeaves.push_back(leaf.getLeaf());
    }
    const auto& entries = storage->band.entries();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, refinedLeaves.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          std::uint32_t record = entries[i].base;
                          for (auto voxel = refinedLeaves[i]->beginValueOn(); voxel;
                               ++voxel, ++record) {
                            voxel.setValue(storage->records[record].distance);
                          }
                        }
                      });
    storage->grid = refined;
  }
  // The target's bounds: the active band's box (contains the surface).
  const openvdb::CoordBBox box = levelSet->evalActiveVoxelBoundingBox();
  Eigen::AlignedBox3d bounds;
  bounds.setEmpty();
  for (int corner = 0; corner < 8; ++corner) {
    const openvdb::Coord c((corner & 1) ? box.max().x() : box.min().x(),
                           (corner & 2) ? box.max().y() : box.min().y(),
                           (corner & 4) ? box.max().z() : box.min().z());
    bounds.extend(storage->indexToWorld(Eigen::Vector3d(c.x(), c.y(), c.z())));
  }
  storage->setDomain(bounds, options.domainPadding, options.domain);
  storage->selectSamples();
  return ApproximantField(std::move(storage));
}

ApproximantField ApproximantField::fromCurve(const CurveTarget& curve, double voxelSize,
                                             double halfWidth,
                                             const ApproximantFieldOptions& options,
                                             const ProgressCallback& progress) {
  ensureOpenVdbInitialized();
  checkBandParameters(voxelSize, halfWidth, "curve field");
  const double radius = halfWidth + 1.0;
  checkBudget(curve.length() / voxelSize * 3.2 * radius * radius + 8 * radius * radius * radius,
              options.maxActiveVoxels, "the field of the " + curve.describe());
  auto storage = std::make_unique<FieldStorage>();
  storage->kind = TargetKind::Curve;
  storage->coarseHalfWidth = std::max(2, options.coarseHalfWidth);
  storage->setTransform(*openvdb::math::Transform::createLinearTransform(voxelSize), "curve field");
  storage->halfWidth = halfWidth;
  storage->estimator = kCurveEstimator;
  storage->label = curve.describe();
  if (progress) progress("field: approximants", 0.0);
  const auto mask = candidateMask(curve.samplePoints(0.5 * voxelSize), *storage,
                                  static_cast<int>(std::ceil(halfWidth)) + 1);
  buildUnsignedBand(
      *storage, *mask, halfWidth,
      [&](const Eigen::Vector3d& centre) { return curve.approximantAtAnyPoint(centre); }, progress);
  storage->setDomain(curve.curveBounds(), options.domainPadding, options.domain);
  storage->selectSamples();
  return ApproximantField(std::move(storage));
}

ApproximantField ApproximantField::fromPoints(const std::vector<Eigen::Vector3d>& points,
                                              double voxelSize, double halfWidth,
                                              const ApproximantFieldOptions& options,
                                              const ProgressCallback& progress) {
  ensureOpenVdbInitialized();
  if (points.empty()) throw InputError("point field: the point set is empty");
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      throw InputError("point field: point " + std::to_string(i) + " is not finite");
    }
  }
  checkBandParameters(voxelSize, halfWidth, "point field");
  Eigen::AlignedBox3d bounds;
  bounds.setEmpty();
  for (const auto& p : points) bounds.extend(p);
  const double radius = 2.0 * halfWidth + 3.0;
  const double boxVoxels = ((bounds.sizes().array() / voxelSize) + radius).prod();
  checkBudget(std::min(static_cast<double>(points.size()) * radius * radius * radius, boxVoxels),
              options.maxActiveVoxels, "the field of " + std::to_string(points.size()) + " points");
  auto storage = std::make_unique<FieldStorage>();
  storage->kind = TargetKind::Points;
  storage->coarseHalfWidth = std::max(2, options.coarseHalfWidth);
  storage->setTransform(*openvdb::math::Transform::createLinearTransform(voxelSize), "point field");
  storage->halfWidth = halfWidth;
  storage->estimator = kPointsEstimator;
  storage->label = std::to_string(points.size()) + " points";
  PointCloud cloud{&points};
  using PointTree =
      nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                          PointCloud, 3, std::uint32_t>;
  // The constructor builds the index.
  const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  if (progress) progress("field: approximants", 0.0);
  const auto mask = candidateMask(points, *storage, static_cast<int>(std::ceil(halfWidth)) + 1);
  buildUnsignedBand(
      *storage, *mask, halfWidth,
      [&](const Eigen::Vector3d& centre) {
        std::uint32_t index = 0;
        double squared = 0.0;
        nanoflann::KNNResultSet<double, std::uint32_t> result(1);
        result.init(&index, &squared);
        const double query[3] = {centre.x(), centre.y(), centre.z()};
        tree.findNeighbors(result, query, nanoflann::SearchParams());
        Approximant a;
        a.kind = TargetKind::Points;
        a.origin = centre;
        a.footpoint = points[index];
        const Eigen::Vector3d offset = centre - a.footpoint;
        a.distance = offset.norm();
        a.normal =
            a.distance > 0.0 ? Eigen::Vector3d(offset / a.distance) : Eigen::Vector3d::UnitZ();
        a.tangent = tangentBasis(a.normal)[0];
        return a;
      },
      progress);
  storage->setDomain(bounds, options.domainPadding, options.domain);
  storage->selectSamples();
  return ApproximantField(std::move(storage));
}

// ---- queries -----------------------------------------------------------------------------------

TargetKind ApproximantField::kind() const {
  return storage_->kind;
}
Eigen::AlignedBox3d ApproximantField::domain() const {
  return storage_->domain;
}
openvdb::FloatGrid::ConstPtr ApproximantField::distanceGrid() const {
  return storage_->grid;
}
double ApproximantField::voxelSize() const {
  return storage_->voxelSize;
}
double ApproximantField::halfWidth() const {
  return storage_->halfWidth;
}
int ApproximantField::levelCount() const {
  storage_->ensureCoarseLevels({});
  return 1 + static_cast<int>(storage_->coarse.size());
}
void ApproximantField::buildCoarseLevels(const ProgressCallback& progress) const {
  storage_->ensureCoarseLevels(progress);
}
bool ApproximantField::coarseLevelsBuilt() const {
  return storage_->coarseLevelsBuilt();
}
double ApproximantField::sampleError() const {
  return storage_->sampleError;
}

double ApproximantField::coarseDistanceErrorBound(int level) const {
  return std::sqrt(3.0) * std::ldexp(storage_->voxelSize, level) + storage_->sampleError;
}

double ApproximantField::resolution() const {
  return voxelSize();
}

std::string ApproximantField::describe() const {
  return std::string(targetKindName(storage_->kind)) + " field (" +
         std::to_string(storage_->records.size()) + " band voxels, voxel size " +
         formatNumber(storage_->voxelSize) + ") of " + storage_->label;
}

ApproximantField::Accessor::Accessor(const ApproximantField& field)
    : field_(field), cachedLeaf_(1, -1), cachedOrigin_(1) {}

Approximant ApproximantField::Accessor::approximantAt(const Eigen::Vector3d& point) {
  const FieldStorage& storage = *field_.storage_;
  if (!point.allFinite()) throw InputError("field query: the point is not finite");
  if (!storage.domain.contains(point)) {
    const double outside = std::sqrt(storage.domain.squaredExteriorDistance(point));
    throw InputError("the point " + formatPoint(point) + " lies " + formatNumber(outside) +
                     " outside the field's working domain " + formatPoint(storage.domain.min()) +
                     " to " + formatPoint(storage.domain.max()));
  }
  const Eigen::Vector3d index = storage.worldToIndex(point);
  const auto lookup = [&](int level, const LeafTable& table,
                          const openvdb::Coord& ijk) -> std::int64_t {
    const openvdb::Coord origin = LeafTable::blockOrigin(ijk);
    std::int64_t& cached = cachedLeaf_[static_cast<std::size_t>(level)];
    if (cached < 0 || cachedOrigin_[static_cast<std::size_t>(level)] != origin) {
      cached = table.findLeaf(ijk);
      cachedOrigin_[static_cast<std::size_t>(level)] = origin;
      if (cached < 0) return -1;
    }
    return LeafTable::recordIndex(table.entries()[static_cast<std::size_t>(cached)], ijk);
  };
  {
    const openvdb::Coord ijk = roundToCoord(index);
    const std::int64_t record = lookup(0, storage.band, ijk);
    if (record >= 0) {
      lastLevel_ = 0;
      Approximant a = storage.decodeBand(static_cast<std::uint32_t>(record), ijk);
      transportTo(a, point);
      return a;
    }
  }
  field_.storage_->ensureCoarseLevels({});
  if (cachedLeaf_.size() < storage.coarse.size() + 1) {
    cachedLeaf_.resize(storage.coarse.size() + 1, -1);
    cachedOrigin_.resize(storage.coarse.size() + 1);
  }
  for (std::size_t i = 0; i < storage.coarse.size(); ++i) {
    const CoarseLevel& level = storage.coarse[i];
    const double scale = std::ldexp(1.0, level.level);
    const openvdb::Coord ijk = roundToCoord(index / scale);
    const std::int64_t record = lookup(static_cast<int>(i) + 1, level.table, ijk);
    if (record >= 0) {
      lastLevel_ = level.level;
      // The sample nearest to the coarse voxel's centre, seen from the query point itself.
      return storage.decodeCoarse(level.sampleOf[static_cast<std::size_t>(record)], index);
    }
  }
  throw RuntimeFailure("internal error: no level of the field covers the point " +
                       formatPoint(point) + " inside its domain");
}

Approximant ApproximantField::approximantAt(const Eigen::Vector3d& point) const {
  Accessor accessor(*this);
  return accessor.approximantAt(point);
}

std::vector<Approximant> ApproximantField::approximantsAt(
    const std::vector<Eigen::Vector3d>& points) const {
  // Validate first so the error names the first bad point whatever the thread count.
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite() || !storage_->domain.contains(points[i])) {
      try {
        approximantAt(points[i]);
      } catch (const InputError& error) {
        throw InputError("query point " + std::to_string(i) + ": " + error.what());
      }
    }
  }
  std::vector<Approximant> result(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      Accessor accessor(*this);
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        result[i] = accessor.approximantAt(points[i]);
                      }
                    });
  return result;
}

// ---- statistics --------------------------------------------------------------------------------

FieldStatistics ApproximantField::statistics() const {
  const FieldStorage& s = *storage_;
  FieldStatistics stats;
  stats.kind = s.kind;
  stats.estimator = s.estimator;
  FieldLevelInfo band;
  band.level = 0;
  band.voxelSize = s.voxelSize;
  band.halfWidth = s.halfWidth;
  band.activeVoxels = s.records.size();
  band.memoryBytes = s.records.capacity() * sizeof(BandRecord) + s.band.memoryBytes();
  stats.levels.push_back(band);
  std::uint64_t total = band.memoryBytes;
  stats.coarseLevelsBuilt = s.coarseLevelsBuilt();
  for (std::size_t i = 0; stats.coarseLevelsBuilt && i < s.coarse.size(); ++i) {
    const CoarseLevel& level = s.coarse[i];
    FieldLevelInfo info;
    info.level = level.level;
    info.voxelSize = std::ldexp(s.voxelSize, level.level);
    info.halfWidth = s.coarseHalfWidth;
    info.activeVoxels = level.sampleOf.size();
    info.memoryBytes =
        level.sampleOf.capacity() * sizeof(std::uint32_t) + level.table.memoryBytes();
    total += info.memoryBytes;
    stats.levels.push_back(info);
  }
  stats.samples = s.sampleRecords.size();
  total += s.sampleRecords.capacity() * sizeof(std::uint32_t) +
           s.sampleFootpoints.capacity() * sizeof(Eigen::Vector3f);
  stats.distanceGridBytes = s.grid->memUsage();
  stats.totalBytes = total + stats.distanceGridBytes;
  const Eigen::Vector3d sizes = s.domain.sizes() / s.voxelSize;
  stats.denseBytes = sizes.prod() * 16.0;
  countFlags(s.records, stats);
  return stats;
}

// ---- standard grids ----------------------------------------------------------------------------

openvdb::GridPtrVec ApproximantField::toGrids() const {
  const FieldStorage& s = *storage_;
  openvdb::GridPtrVec grids;
  // A shallow copy: shares the tree, owns its metadata.
  auto distanceGrid = openvdb::ConstPtrCast<openvdb::FloatGrid>(s.grid)->copy();
  if (distanceGrid->getName().empty()) {
    distanceGrid->setName(s.kind == TargetKind::Surface ? "surface" : "unsigned_distance");
  }
  setFieldMetadata(*distanceGrid, s);
  grids.push_back(distanceGrid);
  const auto& topology = s.grid->tree();
  const auto makeFloat = [&](const std::string& name) {
    auto grid = openvdb::FloatGrid::create(
        openvdb::FloatTree::Ptr(new openvdb::FloatTree(topology, 0.0f, openvdb::TopologyCopy())));
    grid->setTransform(s.grid->transform().copy());
    grid->setName(name);
    return grid;
  };
  const auto makeVector = [&](const std::string& name) {
    auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3STree::Ptr(
        new openvdb::Vec3STree(topology, openvdb::Vec3s(0.0f), openvdb::TopologyCopy())));
    grid->setTransform(s.grid->transform().copy());
    grid->setName(name);
    grid->setVectorType(openvdb::VEC_INVARIANT);
    return grid;
  };
  auto flags = openvdb::Int32Grid::create(
      openvdb::Int32Tree::Ptr(new openvdb::Int32Tree(topology, 0, openvdb::TopologyCopy())));
  flags->setTransform(s.grid->transform().copy());
  flags->setName("flags");

  openvdb::FloatGrid::Ptr scalar0, scalar1;
  openvdb::Vec3SGrid::Ptr vector0, vector1, vector2;
  if (s.kind == TargetKind::Surface) {
    vector0 = makeVector("normal");
    scalar0 = makeFloat("k1");
    scalar1 = makeFloat("k2");
    vector1 = makeVector("e1");
  } else if (s.kind == TargetKind::Curve) {
    vector0 = makeVector("direction");
    vector1 = makeVector("tangent");
    scalar0 = makeFloat("curvature");
    vector2 = makeVector("principal_normal");
  } else {
    vector0 = makeVector("direction");
  }
  const auto toVec = [](const Eigen::Vector3d& v) {
    return openvdb::Vec3s(static_cast<float>(v.x()), static_cast<float>(v.y()),
                          static_cast<float>(v.z()));
  };
  // The same topology gives the same leaf order in every copy.
  std::vector<openvdb::Vec3STree::LeafNodeType*> v0, v1, v2;
  std::vector<openvdb::FloatTree::LeafNodeType*> f0, f1;
  std::vector<openvdb::Int32Tree::LeafNodeType*> fl;
  const auto collect = [](auto& grid, auto& out) {
    if (!grid) return;
    // Leaves without active voxels have no band entry (FieldStorage::buildBandTable skips them).
    for (auto leaf = grid->tree().beginLeaf(); leaf; ++leaf) {
      if (!leaf->getValueMask().isOff()) out.push_back(leaf.getLeaf());
    }
  };
  collect(vector0, v0);
  collect(vector1, v1);
  collect(vector2, v2);
  collect(scalar0, f0);
  collect(scalar1, f1);
  collect(flags, fl);
  const auto& entries = s.band.entries();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, entries.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const LeafEntry& entry = entries[i];
                        std::uint32_t record = entry.base;
                        for (int offset = 0; offset < 512; ++offset) {
                          if (((entry.mask[offset >> 6] >> (offset & 63)) & 1u) == 0) continue;
                          const openvdb::Coord ijk =
                              entry.origin +
                              openvdb::Coord(offset >> 6, (offset >> 3) & 7, offset & 7);
                          const Approximant a = s.decodeBand(record, ijk);
                          const auto index = static_cast<openvdb::Index>(offset);
                          fl[i]->setValueOnly(index, s.records[record].flags);
                          v0[i]->setValueOnly(index, toVec(a.normal));
                          if (s.kind == TargetKind::Surface) {
                            f0[i]->setValueOnly(index, static_cast<float>(a.k1));
                            f1[i]->setValueOnly(index, static_cast<float>(a.k2));
                            v1[i]->setValueOnly(index, toVec(a.tangent));
                          } else if (s.kind == TargetKind::Curve) {
                            v1[i]->setValueOnly(index, toVec(a.tangent));
                            f0[i]->setValueOnly(index, static_cast<float>(a.k1));
                            v2[i]->setValueOnly(index, toVec(a.principalNormal));
                          }
                          ++record;
                        }
                      }
                    });
  for (const openvdb::GridBase::Ptr& grid :
       {openvdb::GridBase::Ptr(vector0), openvdb::GridBase::Ptr(vector1),
        openvdb::GridBase::Ptr(vector2), openvdb::GridBase::Ptr(scalar0),
        openvdb::GridBase::Ptr(scalar1)}) {
    if (grid) grids.push_back(grid);
  }
  grids.push_back(flags);
  return grids;
}

ApproximantField ApproximantField::fromGrids(const openvdb::GridPtrVec& grids,
                                             const std::string& source,
                                             const ApproximantFieldOptions& options,
                                             const ProgressCallback& progress) {
  ensureOpenVdbInitialized();
  // The distance grid: the float grid carrying the field metadata.
  openvdb::FloatGrid::Ptr distance;
  for (const auto& grid : grids) {
    auto floatGrid = openvdb::gridPtrCast<openvdb::FloatGrid>(grid);
    if (floatGrid && (*floatGrid)[kFieldKindMetadata]) {
      distance = floatGrid;
      break;
    }
  }
  const auto findNamed = [&](const std::string& name) -> openvdb::GridBase::Ptr {
    for (const auto& grid : grids) {
      if (grid && grid->getName() == name) return grid;
    }
    return nullptr;
  };
  if (!distance) {
    // A level set alone (e.g. from another tool): compute the approximants now.
    openvdb::FloatGrid::Ptr levelSet;
    for (const auto& grid : grids) {
      auto floatGrid = openvdb::gridPtrCast<openvdb::FloatGrid>(grid);
      if (floatGrid && floatGrid->getGridClass() == openvdb::GRID_LEVEL_SET) {
        levelSet = floatGrid;
        break;
      }
    }
    if (!levelSet) {
      throw InputError(source + " holds neither an approximant field nor a float level set");
    }
    return fromLevelSet(levelSet, options, progress);
  }
  std::string kindName;
  int version = 0;
  try {
    kindName = distance->metaValue<std::string>(kFieldKindMetadata);
    version = distance->metaValue<openvdb::Int32>(kFieldVersionMetadata);
  } catch (const openvdb::Exception&) {
    throw InputError(source + ": the field's metadata (" + std::string(kFieldVersionMetadata) +
                     ") is missing or has the wrong type");
  }
  if (version != kFieldFormatVersion) {
    throw InputError(source + ": field format version " + std::to_string(version) +
                     " is not supported (this d2vdb reads version " +
                     std::to_string(kFieldFormatVersion) + ")");
  }
  auto storage = std::make_unique<FieldStorage>();
  if (kindName == "surface") {
    storage->kind = TargetKind::Surface;
  } else if (kindName == "curve") {
    storage->kind = TargetKind::Curve;
  } else if (kindName == "points") {
    storage->kind = TargetKind::Points;
  } else {
    throw InputError(source + ": unknown field kind '" + kindName + "'");
  }
  storage->coarseHalfWidth = std::max(2, options.coarseHalfWidth);
  storage->setTransform(distance->transform(), source);
  storage->halfWidth = std::abs(static_cast<double>(distance->background())) / storage->voxelSize;
  storage->label = source;
  try {
    storage->estimator = distance->metaValue<std::string>(kFieldEstimatorMetadata);
    const openvdb::Vec3d lo = distance->metaValue<openvdb::Vec3d>(kFieldDomainMinMetadata);
    const openvdb::Vec3d hi = distance->metaValue<openvdb::Vec3d>(kFieldDomainMaxMetadata);
    storage->domain = Eigen::AlignedBox3d(Eigen::Vector3d(lo.x(), lo.y(), lo.z()),
                                          Eigen::Vector3d(hi.x(), hi.y(), hi.z()));
  } catch (const openvdb::Exception&) {
    throw InputError(source + ": the field's estimator or domain metadata is missing");
  }
  if (storage->domain.isEmpty() || !storage->domain.min().allFinite() ||
      !storage->domain.max().allFinite()) {
    throw InputError(source + ": the field's working domain metadata is not a finite box");
  }
  if (distance->activeVoxelCount() == 0) throw InputError(source + ": the field's band is empty");
  if (distance->tree().hasActiveTiles()) {
    throw InputError(source +
                     ": the field's distance grid has active tiles (not a field d2vdb "
                     "wrote)");
  }
  const auto companion = [&](const std::string& name, auto typeTag) {
    using GridT = typename decltype(typeTag)::element_type;
    const auto grid = findNamed(name);
    if (!grid) {
      throw InputError(source + ": the " + kindName + " field's companion grid '" + name +
                       "' is missing");
    }
    auto typed = openvdb::gridPtrCast<GridT>(grid);
    if (!typed) {
      throw InputError(source + ": the companion grid '" + name + "' holds " + grid->valueType() +
                       " values, expected " + GridT::gridType());
    }
    if (!typed->tree().hasSameTopology(distance->tree())) {
      throw InputError(source + ": the companion grid '" + name +
                       "' does not share the distance grid's active voxels");
    }
    if (typed->transform() != distance->transform()) {
      throw InputError(source + ": the companion grid '" + name +
                       "' has a different transform from the distance grid");
    }
    return typed;
  };
  const auto flags = companion("flags", openvdb::Int32Grid::Ptr());
  openvdb::Vec3SGrid::Ptr v0, v1, v2;
  openvdb::FloatGrid::Ptr f0, f1;
  if (storage->kind == TargetKind::Surface) {
    v0 = companion("normal", openvdb::Vec3SGrid::Ptr());
    f0 = companion("k1", openvdb::FloatGrid::Ptr());
    f1 = companion("k2", openvdb::FloatGrid::Ptr());
    v1 = companion("e1", openvdb::Vec3SGrid::Ptr());
  } else if (storage->kind == TargetKind::Curve) {
    v0 = companion("direction", openvdb::Vec3SGrid::Ptr());
    v1 = companion("tangent", openvdb::Vec3SGrid::Ptr());
    f0 = companion("curvature", openvdb::FloatGrid::Ptr());
    v2 = companion("principal_normal", openvdb::Vec3SGrid::Ptr());
  } else {
    v0 = companion("direction", openvdb::Vec3SGrid::Ptr());
  }
  storage->grid = distance;
  const auto leaves = storage->buildBandTable();
  const auto& entries = storage->band.entries();
  std::atomic<bool> invalid{false};
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, entries.size(), 16),
      [&](const tbb::blocked_range<std::size_t>& range) {
        auto a0 = v0->getConstAccessor();
        auto aFlags = flags->getConstAccessor();
        std::optional<openvdb::Vec3SGrid::ConstAccessor> a1, a2;
        std::optional<openvdb::FloatGrid::ConstAccessor> b0, b1;
        if (v1) a1.emplace(v1->getConstAccessor());
        if (v2) a2.emplace(v2->getConstAccessor());
        if (f0) b0.emplace(f0->getConstAccessor());
        if (f1) b1.emplace(f1->getConstAccessor());
        const auto fromVec = [](const openvdb::Vec3s& v) {
          return Eigen::Vector3d(v.x(), v.y(), v.z());
        };
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const auto& leaf = *leaves[i];
          std::uint32_t record = entries[i].base;
          for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel, ++record) {
            const openvdb::Coord ijk = voxel.getCoord();
            Approximant a;
            a.kind = storage->kind;
            a.distance = *voxel;
            a.flags = static_cast<std::uint16_t>(aFlags.getValue(ijk));
            a.normal = storage->toIndexDirection(fromVec(a0.getValue(ijk)));
            if (a1) a.tangent = storage->toIndexDirection(fromVec(a1->getValue(ijk)));
            if (a2) a.principalNormal = storage->toIndexDirection(fromVec(a2->getValue(ijk)));
            if (b0) a.k1 = b0->getValue(ijk);
            if (b1) a.k2 = b1->getValue(ijk);
            const double normalLength = a.normal.norm();
            if (!std::isfinite(a.distance) || !(std::abs(normalLength - 1.0) < 1e-3) ||
                !a.tangent.allFinite() || !std::isfinite(a.k1) || !std::isfinite(a.k2) ||
                !a.principalNormal.allFinite()) {
              invalid = true;
              continue;
            }
            storage->records[record] = storage->encode(a);
          }
        }
      });
  if (invalid) {
    throw InputError(source +
                     ": the field's companion grids hold non-finite values or normals "
                     "that are not unit vectors");
  }
  storage->selectSamples();
  return ApproximantField(std::move(storage));
}

}  // namespace d2vdb
