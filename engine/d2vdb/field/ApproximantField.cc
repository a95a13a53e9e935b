// The squared-distance approximant field: construction, queries and statistics
// (ApproximantField.h).
#include "d2vdb/field/ApproximantField.h"

#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/field/VoxelBudget.h"
#include "d2vdb/field/detail/FieldStorage.h"
#include "d2vdb/field/detail/OpenVdbSetup.h"
#include "d2vdb/field/detail/SeedDilation.h"
#include "d2vdb/field/detail/SurfaceEstimator.h"

namespace d2vdb {

using detail::BandLayout;
using detail::BandRecord;
using detail::CoarseLevel;
using detail::ensureOpenVdbInitialized;
using detail::estimateSurfaceRecords;
using detail::FieldDescription;
using detail::FieldStorage;
using detail::IndexFrame;
using detail::kSurfaceEstimator;
using detail::LeafEntry;
using detail::LeafTable;
using detail::nearestInt;
using detail::RecordCodec;
using detail::tangentBasis;
namespace {

constexpr const char* kCurveEstimator =
    "exact nearest point of the curve at every voxel centre (B-spline: Bezier root isolation; "
    "polyline: nearest segment, curvature from vertex circles)";
constexpr const char* kPointsEstimator = "exact nearest point (k-d tree) at every voxel centre";

// Messages show numbers with 6 significant digits.
constexpr int kMessageDigits = 6;

openvdb::Coord roundToCoord(const Eigen::Vector3d& p) {
  return openvdb::Coord(nearestInt(p.x()), nearestInt(p.y()), nearestInt(p.z()));
}

void checkBandParameters(double voxelSize, double halfWidth, const char* what) {
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize)) {
    throw InputError(std::string(what) + ": the voxel size must be a positive finite number, not " +
                     formatNumber(voxelSize, kMessageDigits));
  }
  checkVoxelSizeIsRepresentable(voxelSize, what);
  if (!(halfWidth >= 1.0) || !std::isfinite(halfWidth) || halfWidth > 64.0) {
    throw InputError(std::string(what) +
                     ": the band half-width must be between 1 and 64 voxels, "
                     "not " +
                     formatNumber(halfWidth, kMessageDigits));
  }
}

void checkBudget(double estimate, const ApproximantFieldOptions& options, const std::string& what) {
  const std::uint64_t limit = options.maxActiveVoxels;
  if (estimate > static_cast<double>(limit)) {
    throw InputError(what + " would need about " + formatNumber(estimate, kMessageDigits) +
                     " active voxels, above the limit of " + std::to_string(limit) +
                     "; use a larger voxel size or a narrower band");
  }
  ResourceBudget budget;
  budget.maxMemoryBytes = options.maxMemoryBytes;
  enforceMemoryBudget(
      {what + " (about " + formatNumber(estimate, kMessageDigits) + " active voxels)",
       estimate * kApproximantBytesPerVoxel,
       "use a larger voxel size or a narrower band (--half-width)"},
      budget);
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
    a.tangent = t.norm() > 1e-9 ? Eigen::Vector3d(t.normalized()) : a.normal.unitOrthogonal();
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
      a.tangent = t.norm() > 1e-9 ? Eigen::Vector3d(t.normalized()) : a.normal.unitOrthogonal();
    }
    if (a.k1 > 0.0) {
      Eigen::Vector3d n = a.principalNormal - a.principalNormal.dot(a.tangent) * a.tangent;
      a.principalNormal =
          n.norm() > 1e-9 ? Eigen::Vector3d(n.normalized()) : a.tangent.unitOrthogonal();
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
    a.tangent = e1.norm() > 1e-9 ? Eigen::Vector3d(e1.normalized()) : normal.unitOrthogonal();
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

// ---- building the band -------------------------------------------------------------------------

/// World centre of voxel `ijk`.
Eigen::Vector3d voxelCenter(const IndexFrame& frame, const openvdb::Coord& ijk) {
  return frame.indexToWorld(Eigen::Vector3d(ijk.x(), ijk.y(), ijk.z()));
}

/// Throws InputError, naming `source` and the voxel, when an approximant from a band's function
/// has non-finite values or a normal that is not a unit vector.
void checkApproximant(const Approximant& a, const openvdb::Coord& ijk, const std::string& source) {
  if (!std::isfinite(a.distance) || !(std::abs(a.normal.norm() - 1.0) < 1e-3) ||
      !a.tangent.allFinite() || !std::isfinite(a.k1) || !std::isfinite(a.k2) ||
      !a.principalNormal.allFinite()) {
    throw InputError(source + ": the approximant of band voxel (" + std::to_string(ijk.x()) + ", " +
                     std::to_string(ijk.y()) + ", " + std::to_string(ijk.z()) +
                     ") has non-finite values or a normal that is not a unit vector");
  }
}

/// The record of a world-frame approximant (directions turned into the index frame).
BandRecord encodeWorld(const RecordCodec& codec, Approximant a) {
  const IndexFrame& frame = codec.frame();
  a.normal = frame.toIndexDirection(a.normal);
  a.tangent = frame.toIndexDirection(a.tangent);
  a.principalNormal = frame.toIndexDirection(a.principalNormal);
  return codec.encode(a);
}

/// The bounding box (world) of the layout's active voxel centres.
Eigen::AlignedBox3d activeVoxelBounds(const BandLayout& layout) {
  const openvdb::CoordBBox box = layout.grid()->evalActiveVoxelBoundingBox();
  Eigen::AlignedBox3d bounds;
  bounds.setEmpty();
  for (int corner = 0; corner < 8; ++corner) {
    const openvdb::Coord c((corner & 1) ? box.max().x() : box.min().x(),
                           (corner & 2) ? box.max().y() : box.min().y(),
                           (corner & 4) ? box.max().z() : box.min().z());
    bounds.extend(voxelCenter(layout.frame(), c));
  }
  return bounds;
}

/// The records of a band whose voxels are given (FieldBand::activeVoxelsOf()), in the layout's
/// order, from the band's approximant functions.
std::vector<BandRecord> recordsOfGridBand(const FieldBand& band, const BandLayout& layout,
                                          const RecordCodec& codec, const std::string& source) {
  const auto& entries = layout.table().entries();
  std::vector<BandRecord> records(layout.voxelCount());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, entries.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const FieldBand::VoxelApproximant approximant = band.approximantFactory()();
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const LeafEntry& entry = entries[i];
                        std::uint32_t record = entry.base;
                        entry.forEachOn([&](int offset) {
                          const openvdb::Coord ijk = entry.voxel(offset);
                          const Approximant a = approximant(ijk, voxelCenter(layout.frame(), ijk));
                          checkApproximant(a, ijk, source);
                          records[record++] = encodeWorld(codec, a);
                        });
                      }
                    });
  return records;
}

/// The voxels containing `seeds` dilated so as to include every voxel whose centre lies within
/// `radius` voxels of a seed (detail::seedDilation()).
openvdb::MaskGrid::Ptr seedCandidates(const std::vector<Eigen::Vector3d>& seeds,
                                      const IndexFrame& frame, double radius) {
  auto mask = openvdb::MaskGrid::create(false);
  auto accessor = mask->getAccessor();
  for (const Eigen::Vector3d& p : seeds) accessor.setValueOn(roundToCoord(frame.worldToIndex(p)));
  const detail::SeedDilation dilation = detail::seedDilation(radius);
  if (dilation.cubeSteps > 0) {
    openvdb::tools::dilateActiveValues(mask->tree(), dilation.cubeSteps,
                                       openvdb::tools::NN_FACE_EDGE_VERTEX,
                                       openvdb::tools::IGNORE_TILES);
  }
  if (dilation.diamondSteps > 0) {
    openvdb::tools::dilateActiveValues(mask->tree(), dilation.diamondSteps, openvdb::tools::NN_FACE,
                                       openvdb::tools::IGNORE_TILES);
  }
  return mask;
}

/// A band found from seeds (FieldBand::nearSeeds()): its layout (a new distance grid) and records.
/// Throws InputError when more than options.maxActiveVoxels voxels are kept or their memory
/// exceeds options.maxMemoryBytes, before making the grid.
std::pair<BandLayout, std::vector<BandRecord>> seedBand(const FieldBand& band,
                                                        const ApproximantFieldOptions& options,
                                                        const std::string& source,
                                                        const ProgressCallback& progress) {
  const double h = band.voxelSize();
  const double limit = band.halfWidth() * h;
  const IndexFrame frame(*openvdb::math::Transform::createLinearTransform(h), source);
  const RecordCodec codec(band.kind(), frame);
  const auto mask = seedCandidates(band.seeds(), frame, band.halfWidth() + band.seedReach());
  std::vector<const openvdb::MaskGrid::TreeType::LeafNodeType*> leaves;
  for (auto leaf = mask->tree().cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf.getLeaf());
  // The kept voxels of each candidate leaf, in offset order, with their records.
  struct Kept {
    std::vector<std::uint16_t> offsets;
    std::vector<BandRecord> records;
  };
  std::vector<Kept> kept(leaves.size());
  // Blocks of leaves in sequence (for progress), the leaves of a block in parallel.
  const std::size_t blocks =
      std::max<std::size_t>(1, std::min<std::size_t>(40, leaves.size() / 64));
  for (std::size_t block = 0; block < blocks; ++block) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(leaves.size() * block / blocks,
                                                      leaves.size() * (block + 1) / blocks, 4),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        const FieldBand::VoxelApproximant approximant = band.approximantFactory()();
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          for (auto voxel = leaves[i]->cbeginValueOn(); voxel; ++voxel) {
                            const openvdb::Coord ijk = voxel.getCoord();
                            const Approximant a = approximant(ijk, voxelCenter(frame, ijk));
                            if (std::abs(a.distance) >= limit) continue;  // NaN is checked
                            checkApproximant(a, ijk, source);
                            kept[i].offsets.push_back(static_cast<std::uint16_t>(voxel.pos()));
                            kept[i].records.push_back(encodeWorld(codec, a));
                          }
                        }
                      });
    if (progress) progress("field: approximants", 0.8 * static_cast<double>(block + 1) / blocks);
  }
  std::uint64_t keptCount = 0;
  for (const Kept& leaf : kept) keptCount += leaf.offsets.size();
  if (keptCount == 0) {
    throw InputError("the target has no voxel within the band at this voxel size");
  }
  checkBudget(static_cast<double>(keptCount), options, "the band of " + source);
  // The distance grid, leaf by leaf in candidate order.
  auto grid = openvdb::FloatGrid::create(static_cast<float>(limit));
  grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
  if (band.kind() == TargetKind::Surface) {
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setName("surface");
  } else {
    grid->setGridClass(openvdb::GRID_UNKNOWN);
    grid->setName("unsigned_distance");
  }
  {
    auto accessor = grid->getAccessor();
    for (std::size_t i = 0; i < leaves.size(); ++i) {
      const openvdb::Coord origin = leaves[i]->origin();
      for (std::size_t k = 0; k < kept[i].offsets.size(); ++k) {
        const int offset = kept[i].offsets[k];
        accessor.setValueOn(origin + openvdb::Coord(offset >> 6, (offset >> 3) & 7, offset & 7),
                            kept[i].records[k].distance);
      }
    }
  }
  if (band.kind() == TargetKind::Surface) openvdb::tools::signedFloodFill(grid->tree());
  BandLayout layout(grid, source);
  // Records in the layout's order: each of its leaves takes the records kept for the candidate
  // leaf with the same origin (in offset order, the order of the leaf's mask).
  std::unordered_map<openvdb::Coord, std::size_t> candidateOf;
  for (std::size_t i = 0; i < leaves.size(); ++i) candidateOf.emplace(leaves[i]->origin(), i);
  const auto& entries = layout.table().entries();
  std::vector<BandRecord> records(layout.voxelCount());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, entries.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const Kept& source = kept[candidateOf.at(entries[i].origin)];
                        std::copy(source.records.begin(), source.records.end(),
                                  records.begin() + entries[i].base);
                      }
                    });
  if (progress) progress("field: approximants", 1.0);
  return {std::move(layout), std::move(records)};
}

/// Checks a nearSeeds() band's parameters and seeds; the target bounds are the seeds' box.
Eigen::AlignedBox3d checkSeeds(const FieldBand& band, const std::string& source) {
  checkBandParameters(band.voxelSize(), band.halfWidth(), source.c_str());
  if (!(band.seedReach() > 0.0 && band.seedReach() <= 8.0)) {
    throw InputError(source + ": the seeds' reach must lie in (0, 8] voxels, not " +
                     formatNumber(band.seedReach(), kMessageDigits));
  }
  if (band.seeds().empty()) throw InputError(source + ": no seed points given");
  Eigen::AlignedBox3d bounds;
  bounds.setEmpty();
  for (std::size_t i = 0; i < band.seeds().size(); ++i) {
    if (!band.seeds()[i].allFinite()) {
      throw InputError(source + ": seed point " + std::to_string(i) + " is not finite");
    }
    bounds.extend(band.seeds()[i]);
  }
  return bounds;
}

}  // namespace

// ---- construction ------------------------------------------------------------------------------

ApproximantField::ApproximantField(std::unique_ptr<FieldStorage> storage)
    : storage_(std::move(storage)) {}
ApproximantField::ApproximantField(ApproximantField&&) noexcept = default;
ApproximantField& ApproximantField::operator=(ApproximantField&&) noexcept = default;
ApproximantField::~ApproximantField() = default;

ApproximantField ApproximantField::fromBand(const FieldBand& band,
                                            const ApproximantFieldOptions& options,
                                            const ProgressCallback& progress) {
  ensureOpenVdbInitialized();
  const std::string source = band.label().empty() ? std::string("field band") : band.label();
  if (!band.approximantFactory()) {
    throw InputError(source + ": the band has no approximant function");
  }
  FieldDescription description;
  description.kind = band.kind();
  description.estimator = band.estimator();
  description.label = band.label();
  description.coarseHalfWidth = std::max(2, options.coarseHalfWidth);
  if (progress) progress("field: approximants", 0.0);
  if (band.grid()) {
    BandLayout layout(band.grid(), source);
    description.halfWidth = layout.halfWidth();
    description.domain =
        detail::workingDomain(band.targetBounds().value_or(activeVoxelBounds(layout)),
                              options.domainPadding, options.domain, layout.frame().voxelSize());
    const RecordCodec codec(band.kind(), layout.frame());
    std::vector<BandRecord> records = recordsOfGridBand(band, layout, codec, source);
    if (progress) progress("field: approximants", 1.0);
    return ApproximantField(
        std::make_unique<FieldStorage>(description, std::move(layout), std::move(records)));
  }
  const Eigen::AlignedBox3d seedBounds = checkSeeds(band, source);
  description.halfWidth = band.halfWidth();
  description.domain =
      detail::workingDomain(band.targetBounds().value_or(seedBounds), options.domainPadding,
                            options.domain, band.voxelSize());
  auto [layout, records] = seedBand(band, options, source, progress);
  return ApproximantField(
      std::make_unique<FieldStorage>(description, std::move(layout), std::move(records)));
}

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
  const IndexFrame frame(levelSet->transform(), source);
  const std::uint64_t active = levelSet->activeVoxelCount();
  if (active == 0) throw InputError(source + " has no active voxels (an empty band)");
  const double halfWidth =
      std::abs(static_cast<double>(levelSet->background())) / frame.voxelSize();
  if (!(halfWidth >= 2.0 - 1e-6)) {
    throw InputError(source + " has a band half-width of " +
                     formatNumber(halfWidth, kMessageDigits) +
                     " voxels (background / voxel size); the curvature estimator needs at least 2;"
                     " rebuild it with --half-width 3");
  }
  checkBudget(1.4 * static_cast<double>(active), options, "the approximant field of " + source);
  if (levelSet->tree().hasActiveTiles()) {
    auto voxelized = levelSet->deepCopy();
    voxelized->tree().voxelizeActiveTiles();
    levelSet = voxelized;
  }
  BandLayout layout(levelSet, source);
  FieldDescription description;
  description.kind = TargetKind::Surface;
  description.estimator = kSurfaceEstimator;
  description.label = source;
  description.halfWidth = layout.halfWidth();
  description.coarseHalfWidth = std::max(2, options.coarseHalfWidth);
  // The target's bounds: the active band's box (contains the surface).
  description.domain = detail::workingDomain(activeVoxelBounds(layout), options.domainPadding,
                                             options.domain, frame.voxelSize());
  if (progress) progress("field: approximants", 0.0);
  std::vector<BandRecord> records =
      estimateSurfaceRecords(layout, RecordCodec(TargetKind::Surface, layout.frame()), progress);
  // The storage makes the distance grid hold the distances the footpoints imply (the input's
  // values corrected by the projection onto the zero level), so grid, records and files agree.
  return ApproximantField(
      std::make_unique<FieldStorage>(description, std::move(layout), std::move(records)));
}

ApproximantField ApproximantField::fromCurve(const CurveTarget& curve, double voxelSize,
                                             double halfWidth,
                                             const ApproximantFieldOptions& options,
                                             const ProgressCallback& progress) {
  checkBandParameters(voxelSize, halfWidth, "curve field");
  const double radius = halfWidth + 1.0;
  checkBudget(curve.length() / voxelSize * 3.2 * radius * radius + 8 * radius * radius * radius,
              options, "the field of the " + curve.describe());
  FieldBand band = FieldBand::nearSeeds(TargetKind::Curve, curve.samplePoints(0.5 * voxelSize),
                                        voxelSize, halfWidth);
  band.setApproximants([&](const openvdb::Coord&, const Eigen::Vector3d& center) {
        return curve.approximantAtAnyPoint(center);
      })
      .setEstimator(kCurveEstimator)
      .setLabel(curve.describe())
      .setTargetBounds(curve.curveBounds());
  return fromBand(band, options, progress);
}

ApproximantField ApproximantField::fromPoints(const std::vector<Eigen::Vector3d>& points,
                                              double voxelSize, double halfWidth,
                                              const ApproximantFieldOptions& options,
                                              const ProgressCallback& progress) {
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
              options, "the field of " + std::to_string(points.size()) + " points");
  PointCloud cloud{&points};
  using PointTree =
      nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                          PointCloud, 3, std::uint32_t>;
  // The constructor builds the index.
  const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  FieldBand band = FieldBand::nearSeeds(TargetKind::Points, points, voxelSize, halfWidth);
  band.setApproximants([&](const openvdb::Coord&, const Eigen::Vector3d& center) {
        std::uint32_t index = 0;
        double squared = 0.0;
        nanoflann::KNNResultSet<double, std::uint32_t> result(1);
        result.init(&index, &squared);
        const double query[3] = {center.x(), center.y(), center.z()};
        tree.findNeighbors(result, query, nanoflann::SearchParams());
        Approximant a;
        a.kind = TargetKind::Points;
        a.origin = center;
        a.footpoint = points[index];
        const Eigen::Vector3d offset = center - a.footpoint;
        a.distance = offset.norm();
        a.normal =
            a.distance > 0.0 ? Eigen::Vector3d(offset / a.distance) : Eigen::Vector3d::UnitZ();
        a.tangent = tangentBasis(a.normal)[0];
        return a;
      })
      .setEstimator(kPointsEstimator)
      .setLabel(std::to_string(points.size()) + " points")
      .setTargetBounds(bounds);
  return fromBand(band, options, progress);
}

// ---- queries -----------------------------------------------------------------------------------

TargetKind ApproximantField::kind() const {
  return storage_->kind();
}
Eigen::AlignedBox3d ApproximantField::domain() const {
  return storage_->domain();
}
openvdb::FloatGrid::ConstPtr ApproximantField::distanceGrid() const {
  return storage_->grid();
}
double ApproximantField::voxelSize() const {
  return storage_->voxelSize();
}
double ApproximantField::halfWidth() const {
  return storage_->halfWidth();
}
int ApproximantField::levelCount() const {
  storage_->ensureCoarseLevels({});
  return 1 + static_cast<int>(storage_->coarseLevels().size());
}
void ApproximantField::buildCoarseLevels(const ProgressCallback& progress) const {
  storage_->ensureCoarseLevels(progress);
}
bool ApproximantField::coarseLevelsBuilt() const {
  return storage_->coarseLevelsBuilt();
}
double ApproximantField::sampleError() const {
  return storage_->samples().error;
}

double ApproximantField::coarseDistanceErrorBound(int level) const {
  return std::sqrt(3.0) * std::ldexp(storage_->voxelSize(), level) + storage_->samples().error;
}

double ApproximantField::resolvedLength() const {
  return voxelSize();
}

std::string ApproximantField::describe() const {
  return std::string(targetKindName(storage_->kind())) + " field (" +
         std::to_string(storage_->records().size()) + " band voxels, voxel size " +
         formatNumber(storage_->voxelSize(), kMessageDigits) + ") of " + storage_->label();
}

ApproximantField::Accessor::Accessor(const ApproximantField& field)
    : field_(field), cachedLeaf_(1, -1), cachedOrigin_(1) {}

Approximant ApproximantField::Accessor::approximantAt(const Eigen::Vector3d& point) {
  const FieldStorage& storage = *field_.storage_;
  if (!point.allFinite()) throw InputError("field query: the point is not finite");
  if (!storage.domain().contains(point)) {
    const double outside = std::sqrt(storage.domain().squaredExteriorDistance(point));
    throw InputError("the point " + formatPoint(point, kMessageDigits) + " lies " +
                     formatNumber(outside, kMessageDigits) +
                     " outside the field's working domain " +
                     formatPoint(storage.domain().min(), kMessageDigits) + " to " +
                     formatPoint(storage.domain().max(), kMessageDigits));
  }
  const Eigen::Vector3d index = storage.frame().worldToIndex(point);
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
    const std::int64_t record = lookup(0, storage.band(), ijk);
    if (record >= 0) {
      lastLevel_ = 0;
      Approximant a = storage.decodeBand(static_cast<std::uint32_t>(record), ijk);
      transportTo(a, point);
      return a;
    }
  }
  field_.storage_->ensureCoarseLevels({});
  if (cachedLeaf_.size() < storage.coarseLevels().size() + 1) {
    cachedLeaf_.resize(storage.coarseLevels().size() + 1, -1);
    cachedOrigin_.resize(storage.coarseLevels().size() + 1);
  }
  for (std::size_t i = 0; i < storage.coarseLevels().size(); ++i) {
    const CoarseLevel& level = storage.coarseLevels()[i];
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
                       formatPoint(point, kMessageDigits) + " inside its domain");
}

std::optional<Approximant> ApproximantField::Accessor::bandApproximant(const openvdb::Coord& ijk) {
  const FieldStorage& storage = *field_.storage_;
  std::int64_t& cached = cachedLeaf_[0];
  const openvdb::Coord origin = LeafTable::blockOrigin(ijk);
  if (cached < 0 || cachedOrigin_[0] != origin) {
    cached = storage.band().findLeaf(ijk);
    cachedOrigin_[0] = origin;
    if (cached < 0) return std::nullopt;
  }
  const std::int64_t record =
      LeafTable::recordIndex(storage.band().entries()[static_cast<std::size_t>(cached)], ijk);
  if (record < 0) return std::nullopt;
  return storage.decodeBand(static_cast<std::uint32_t>(record), ijk);
}

Approximant ApproximantField::approximantAt(const Eigen::Vector3d& point) const {
  Accessor accessor(*this);
  return accessor.approximantAt(point);
}

std::vector<Approximant> ApproximantField::approximantsAt(
    const std::vector<Eigen::Vector3d>& points) const {
  // Validate first so the error names the first bad point whatever the thread count.
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite() || !storage_->domain().contains(points[i])) {
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

const std::string& ApproximantField::estimator() const {
  return storage_->estimator();
}

// ---- statistics --------------------------------------------------------------------------------

FieldStatistics ApproximantField::statistics() const {
  const FieldStorage& s = *storage_;
  FieldStatistics stats;
  stats.kind = s.kind();
  stats.estimator = s.estimator();
  FieldLevelInfo band;
  band.level = 0;
  band.voxelSize = s.voxelSize();
  band.halfWidth = s.halfWidth();
  band.activeVoxels = s.records().size();
  band.memoryBytes = s.records().capacity() * sizeof(BandRecord) + s.band().memoryBytes();
  stats.levels.push_back(band);
  std::uint64_t total = band.memoryBytes;
  stats.coarseLevelsBuilt = s.coarseLevelsBuilt();
  for (std::size_t i = 0; stats.coarseLevelsBuilt && i < s.coarseLevels().size(); ++i) {
    const CoarseLevel& level = s.coarseLevels()[i];
    FieldLevelInfo info;
    info.level = level.level;
    info.voxelSize = std::ldexp(s.voxelSize(), level.level);
    info.halfWidth = s.coarseHalfWidth();
    info.activeVoxels = level.sampleOf.size();
    info.memoryBytes =
        level.sampleOf.capacity() * sizeof(std::uint32_t) + level.table.memoryBytes();
    total += info.memoryBytes;
    stats.levels.push_back(info);
  }
  stats.samples = s.samples().records.size();
  total += s.samples().records.capacity() * sizeof(std::uint32_t) +
           s.samples().footpoints.capacity() * sizeof(Eigen::Vector3f);
  stats.distanceGridBytes = s.grid()->memUsage();
  stats.totalBytes = total + stats.distanceGridBytes;
  const Eigen::Vector3d sizes = s.domain().sizes() / s.voxelSize();
  stats.denseBytes = sizes.prod() * 16.0;
  countFlags(s.records(), stats);
  return stats;
}

}  // namespace d2vdb
