// Compact records, leaf tables, decoding and the coarse levels of ApproximantField
// (FieldStorage.h).
#include "d2vdb/field/detail/FieldStorage.h"

#include <openvdb/math/Half.h>
#include <openvdb/tools/Morphology.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/detail/NearestPointTree.h"

namespace d2vdb::detail {
namespace {

/// Codes per quadrant of the diamond angle (encodeAngle()).
constexpr double kAngleSteps = 16384.0;

constexpr double kSqrt3 = 1.7320508075688772935;
/// Whether coarse level `level` is the top one: its reach (halfWidth voxels of 2^level band voxels)
/// spans the domain's index-space diagonal plus one of its voxels.
bool isTopLevel(int halfWidth, int level, double diagonal) {
  const double scale = std::ldexp(1.0, level);
  return halfWidth * scale >= diagonal + scale;
}

/// Relative rounding of a nearest-sample distance found with float arithmetic (generous).
constexpr double kSearchRounding = 1e-5;
/// More coarse levels than any domain needs (2^30 voxels across).
constexpr int kMaxCoarseLevels = 30;

/// Steps of 26-neighbour (cube) and 6-neighbour (octahedron) dilation whose combination covers
/// every lattice point within `radius` of an active one (in voxels) with the fewest extra points:
/// the combined region's support k1 |n|_1 + k2 |n|_inf must reach `radius` along the axes, the
/// face and the body diagonals; among those pairs, the smallest mean thickness
/// (1.5 k1 + 0.77 k2, the mean of |n|_1 and |n|_inf over directions) wins.
std::pair<int, int> dilationSteps(double radius) {
  const int total = static_cast<int>(std::ceil(radius));
  std::pair<int, int> best{total, 0};
  double bestCost = 1.5 * total;
  for (int cube = 0; cube <= total; ++cube) {
    const double faceDiagonal = (radius - cube * std::sqrt(2.0)) * std::sqrt(2.0);
    const double bodyDiagonal = (radius - cube * kSqrt3) * kSqrt3;
    const int octahedron = std::max({0, static_cast<int>(std::ceil(radius - cube)),
                                     static_cast<int>(std::ceil(faceDiagonal)),
                                     static_cast<int>(std::ceil(bodyDiagonal))});
    const double cost = 1.5 * cube + 0.77 * octahedron;
    if (cost < bestCost) {
      bestCost = cost;
      best = {cube, octahedron};
    }
  }
  return best;
}

/// Fills the leaves of one coarse level (one filler per thread): for every candidate cell, the
/// nearest sample to its centre, unless the cell can never answer a query.
class CoarseLeafFiller {
 public:
  CoarseLeafFiller(const NearestPointTree& tree, const std::vector<Eigen::Vector3f>& samples,
                   const LeafTable& band, const CoarseLevel* finer, int level, double reach,
                   bool top)
      : tree_(tree),
        samples_(samples),
        finer_(finer),
        level_(level),
        scale_(std::ldexp(1.0, level)),
        reach_(reach),
        top_(top),
        bandCursor_(band) {
    if (finer_ != nullptr) finerCursor_.emplace(finer_->table);
  }

  /// Fills `entry` (origin and mask) and `kept` (the kept cells' samples, in mask order) from the
  /// candidate cells of `leaf`.
  void fill(const openvdb::MaskGrid::TreeType::LeafNodeType& leaf, LeafEntry& entry,
            std::vector<std::uint32_t>& kept) {
    entry.origin = leaf.origin();
    // Lower bounds on the nearest-sample distance at the leaf's cells (index units): the distance
    // to a sample set is 1-Lipschitz, so a cell whose face neighbour is known to lie beyond the
    // reach plus one cell needs no search.
    std::array<double, 512> lower;
    lower.fill(-std::numeric_limits<double>::infinity());
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      const openvdb::Coord ijk = voxel.getCoord();
      const int offset = static_cast<int>(voxel.pos());
      if (!top_) {
        double neighbour = -std::numeric_limits<double>::infinity();
        if ((offset & 7) != 0) neighbour = std::max(neighbour, lower[offset - 1]);
        if ((offset & 56) != 0) neighbour = std::max(neighbour, lower[offset - 8]);
        if ((offset & 448) != 0) neighbour = std::max(neighbour, lower[offset - 64]);
        if (neighbour - scale_ > reach_) {
          lower[offset] = neighbour - scale_;
          continue;
        }
      }
      if (level_ == 1 && answeredByBand(ijk)) continue;
      const Eigen::Vector3d centre = Eigen::Vector3d(ijk.x(), ijk.y(), ijk.z()) * scale_;
      const std::int64_t known = knownSample(ijk);
      const std::uint32_t sample = known >= 0 ? static_cast<std::uint32_t>(known)
                                              : tree_.nearest(centre.cast<float>(), hint_).index;
      hint_ = sample;
      const double distance = (samples_[sample].cast<double>() - centre).norm();
      // The answer is a nearest sample up to float rounding of the search.
      lower[offset] = distance * (1.0 - kSearchRounding);
      if (!top_ && distance > reach_) continue;
      entry.mask[offset >> 6] |= std::uint64_t{1} << (offset & 63);
      kept.push_back(sample);
    }
  }

 private:
  /// Whether the band answers every query that would reach level-1 cell `ijk`: those round to one
  /// of the 27 band voxels 2 ijk + {-1, 0, 1}^3.
  bool answeredByBand(const openvdb::Coord& ijk) {
    const openvdb::Coord centre(2 * ijk.x(), 2 * ijk.y(), 2 * ijk.z());
    if (bandCursor_.record(centre) < 0) return false;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          if (bandCursor_.record(centre + openvdb::Coord(dx, dy, dz)) < 0) return false;
        }
      }
    }
    return true;
  }

  /// A cell centre of this level is also one of the finer level's (index 2 ijk there): where that
  /// level kept it, its nearest sample is already known. -1 otherwise.
  std::int64_t knownSample(const openvdb::Coord& ijk) {
    if (!finerCursor_) return -1;
    const std::int64_t record =
        finerCursor_->record(openvdb::Coord(2 * ijk.x(), 2 * ijk.y(), 2 * ijk.z()));
    if (record < 0) return -1;
    return static_cast<std::int64_t>(finer_->sampleOf[static_cast<std::size_t>(record)]);
  }

  const NearestPointTree& tree_;
  const std::vector<Eigen::Vector3f>& samples_;
  const CoarseLevel* finer_;
  int level_;
  double scale_;
  double reach_;
  bool top_;
  LeafCursor bandCursor_;
  std::optional<LeafCursor> finerCursor_;
  /// The previous cell's answer, a near neighbour's: each search starts from it (answers are exact,
  /// so they do not depend on it).
  std::uint32_t hint_ = 0;
};

}  // namespace

// ---- LeafTable ---------------------------------------------------------------------------------

std::size_t LeafTable::hash(const openvdb::Coord& c) const {
  const auto u = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)); };
  const std::uint64_t h = (u(c.x()) * 0x9E3779B97F4A7C15ull) ^ (u(c.y()) * 0xC2B2AE3D27D4EB4Full) ^
                          (u(c.z()) * 0x165667B19E3779F9ull);
  return static_cast<std::size_t>(h ^ (h >> 29)) & slotMask_;
}

std::uint64_t LeafTable::build(std::vector<LeafEntry> entries) {
  entries_ = std::move(entries);
  std::uint64_t total = 0;
  for (LeafEntry& entry : entries_) {
    entry.base = static_cast<std::uint32_t>(total);
    std::uint32_t running = 0;
    for (int w = 0; w < 8; ++w) {
      entry.prefix[w] = static_cast<std::uint16_t>(running);
      running += static_cast<std::uint32_t>(countBits(entry.mask[w]));
    }
    total += running;
  }
  if (total > std::numeric_limits<std::uint32_t>::max()) {
    throw InputError("the field has " + std::to_string(total) +
                     " active voxels, more than 2^32 records can address");
  }
  std::size_t capacity = 16;
  while (capacity < 2 * entries_.size()) capacity *= 2;
  slots_.assign(capacity, -1);
  slotMask_ = capacity - 1;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    std::size_t slot = hash(entries_[i].origin);
    while (slots_[slot] != -1) slot = (slot + 1) & slotMask_;
    slots_[slot] = static_cast<std::int32_t>(i);
  }
  return total;
}

std::int64_t LeafTable::findLeaf(const openvdb::Coord& ijk) const {
  if (slots_.empty()) return -1;
  const openvdb::Coord origin = blockOrigin(ijk);
  for (std::size_t slot = hash(origin);; slot = (slot + 1) & slotMask_) {
    const std::int32_t index = slots_[slot];
    if (index == -1) return -1;
    if (entries_[static_cast<std::size_t>(index)].origin == origin) return index;
  }
}

// ---- codecs ------------------------------------------------------------------------------------

std::array<std::int16_t, 2> encodeOctahedral(const Eigen::Vector3d& unit) {
  const double l1 = std::abs(unit.x()) + std::abs(unit.y()) + std::abs(unit.z());
  double px = l1 > 0.0 ? unit.x() / l1 : 0.0;
  double py = l1 > 0.0 ? unit.y() / l1 : 0.0;
  if (l1 > 0.0 && unit.z() < 0.0) {
    const double fx = (1.0 - std::abs(py)) * (px >= 0.0 ? 1.0 : -1.0);
    const double fy = (1.0 - std::abs(px)) * (py >= 0.0 ? 1.0 : -1.0);
    px = fx;
    py = fy;
  }
  const auto quantise = [](double v) {
    return static_cast<std::int16_t>(nearestInt(std::clamp(v, -1.0, 1.0) * 32767.0));
  };
  return {quantise(px), quantise(py)};
}

Eigen::Vector3d decodeOctahedral(const std::array<std::int16_t, 2>& code) {
  double px = code[0] / 32767.0, py = code[1] / 32767.0;
  const double z = 1.0 - std::abs(px) - std::abs(py);
  if (z < 0.0) {
    const double fx = (1.0 - std::abs(py)) * (px >= 0.0 ? 1.0 : -1.0);
    const double fy = (1.0 - std::abs(px)) * (py >= 0.0 ? 1.0 : -1.0);
    px = fx;
    py = fy;
  }
  return Eigen::Vector3d(px, py, z).normalized();
}

std::array<Eigen::Vector3d, 2> tangentBasis(const Eigen::Vector3d& unit) {
  const Eigen::Vector3d axis =
      std::abs(unit.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d b1 = axis.cross(unit).normalized();
  return {b1, unit.cross(b1)};
}

std::uint16_t encodeAngle(const Eigen::Vector3d& axis, const Eigen::Vector3d& direction) {
  const auto basis = tangentBasis(axis);
  const double u = direction.dot(basis[0]), v = direction.dot(basis[1]);
  const double l1 = std::abs(u) + std::abs(v);
  if (!(l1 > 0.0)) return 0;
  double diamond;  // [0, 4): quadrants 1 to 4 of the (u, v) plane
  if (v >= 0.0) {
    diamond = u >= 0.0 ? v / l1 : 1.0 - u / l1;
  } else {
    diamond = u <= 0.0 ? 2.0 - v / l1 : 3.0 + u / l1;
  }
  return static_cast<std::uint16_t>(nearestInt(diamond * kAngleSteps) & 0xFFFF);
}

Eigen::Vector3d decodeAngle(const Eigen::Vector3d& axis, std::uint16_t code) {
  const auto basis = tangentBasis(axis);
  const double diamond = code / kAngleSteps;
  double u, v;
  if (diamond < 1.0) {
    u = 1.0 - diamond;
    v = diamond;
  } else if (diamond < 2.0) {
    u = 1.0 - diamond;
    v = 2.0 - diamond;
  } else if (diamond < 3.0) {
    u = diamond - 3.0;
    v = 2.0 - diamond;
  } else {
    u = diamond - 3.0;
    v = diamond - 4.0;
  }
  return (u * basis[0] + v * basis[1]).normalized();
}

std::uint16_t encodeHalf(double value) {
  return openvdb::math::half(static_cast<float>(value)).bits();
}

double decodeHalf(std::uint16_t bits) {
  openvdb::math::half value;
  value.setBits(bits);
  return static_cast<double>(static_cast<float>(value));
}

// ---- records -----------------------------------------------------------------------------------

BandRecord FieldStorage::encode(const Approximant& a) const {
  BandRecord record;
  record.distance = static_cast<float>(a.distance);
  record.flags = a.flags;
  record.normal = encodeOctahedral(a.normal);
  const Eigen::Vector3d normal = decodeOctahedral(record.normal);
  if (kind == TargetKind::Points) return record;
  Eigen::Vector3d tangent = a.tangent - a.tangent.dot(normal) * normal;
  if (tangent.squaredNorm() < 1e-18) tangent = tangentBasis(normal)[0];
  record.angle = encodeAngle(normal, tangent);  // any length
  if (kind == TargetKind::Surface) {
    record.c0 = encodeHalf(a.k1 * voxelSize);
    record.c1 = encodeHalf(a.k2 * voxelSize);
  } else {
    record.c0 = encodeHalf(a.k1 * voxelSize);
    const Eigen::Vector3d decodedTangent = decodeAngle(normal, record.angle);
    Eigen::Vector3d principal =
        a.principalNormal - a.principalNormal.dot(decodedTangent) * decodedTangent;
    if (principal.squaredNorm() < 1e-18) principal = tangentBasis(decodedTangent)[0];
    record.c1 = encodeAngle(decodedTangent, principal);
  }
  return record;
}

Approximant FieldStorage::decodeBand(std::uint32_t recordIndex, const openvdb::Coord& ijk) const {
  const BandRecord& record = records[recordIndex];
  Approximant a;
  a.kind = kind;
  a.flags = record.flags;
  a.distance = record.distance;
  const Eigen::Vector3d centre(ijk.x(), ijk.y(), ijk.z());
  const Eigen::Vector3d normal = decodeOctahedral(record.normal);
  a.origin = indexToWorld(centre);
  a.footpoint = indexToWorld(centre - (a.distance / voxelSize) * normal);
  a.normal = toWorldDirection(normal);
  if (kind == TargetKind::Points) {
    a.tangent = toWorldDirection(tangentBasis(normal)[0]);
    return a;
  }
  const Eigen::Vector3d tangent = decodeAngle(normal, record.angle);
  a.tangent = toWorldDirection(tangent);
  if (kind == TargetKind::Surface) {
    a.k1 = decodeHalf(record.c0) / voxelSize;
    a.k2 = decodeHalf(record.c1) / voxelSize;
  } else {
    a.k1 = decodeHalf(record.c0) / voxelSize;
    if (a.k1 > 0.0) a.principalNormal = toWorldDirection(decodeAngle(tangent, record.c1));
  }
  return a;
}

Approximant FieldStorage::decodeCoarse(std::uint32_t sample, const Eigen::Vector3d& centre) const {
  const BandRecord& record = records[sampleRecords[sample]];
  const Eigen::Vector3d footpoint = sampleFootpoints[sample].cast<double>();
  const Eigen::Vector3d sampleNormal = decodeOctahedral(record.normal);
  Approximant a;
  a.kind = kind;
  a.flags = static_cast<std::uint16_t>((record.flags & ~kFlagFarField) | kFlagFarField);
  a.origin = indexToWorld(centre);
  a.footpoint = indexToWorld(footpoint);
  const Eigen::Vector3d offset = centre - footpoint;
  const double length = offset.norm();
  double sign = 1.0;
  if (kind == TargetKind::Surface && offset.dot(sampleNormal) < 0.0) sign = -1.0;
  const Eigen::Vector3d normal =
      length > 1e-9 ? Eigen::Vector3d(sign * offset / length) : sampleNormal;
  a.distance = sign * length * voxelSize;
  a.normal = toWorldDirection(normal);
  const Eigen::Vector3d sampleTangent = kind == TargetKind::Points
                                            ? tangentBasis(normal)[0]
                                            : decodeAngle(sampleNormal, record.angle);
  Eigen::Vector3d tangent = sampleTangent - sampleTangent.dot(normal) * normal;
  tangent = tangent.norm() > 1e-9 ? Eigen::Vector3d(tangent.normalized()) : tangentBasis(normal)[0];
  a.tangent = toWorldDirection(tangent);
  if (kind == TargetKind::Surface) {
    a.k1 = decodeHalf(record.c0) / voxelSize;
    a.k2 = decodeHalf(record.c1) / voxelSize;
  } else if (kind == TargetKind::Curve) {
    a.k1 = decodeHalf(record.c0) / voxelSize;
    if (a.k1 > 0.0) {
      a.principalNormal = toWorldDirection(decodeAngle(sampleTangent, record.c1));
    }
  }
  return a;
}

// ---- transform, tables, domain -----------------------------------------------------------------

void FieldStorage::setTransform(const openvdb::math::Transform& transform,
                                const std::string& source) {
  if (!transform.isLinear() || !transform.hasUniformScale()) {
    throw InputError(source +
                     ": the grid's transform is not a linear map with cubic voxels; "
                     "the approximant field needs uniform voxels (resample it first)");
  }
  const openvdb::Mat4d matrix = transform.baseMap()->getAffineMap()->getMat4();
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      indexToWorldLinear(column, row) = matrix[row][column];
    }
    indexToWorldOffset[row] = matrix[3][row];
  }
  voxelSize = transform.voxelSize()[0];
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize)) {
    throw InputError(source + ": the grid's voxel size is not a positive finite number");
  }
  rotation = indexToWorldLinear / voxelSize;
  if ((rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 ||
      rotation.determinant() < 0.0) {
    throw InputError(source +
                     ": the grid's transform shears or mirrors its voxels; the "
                     "approximant field needs a rotation and uniform scale");
  }
  axisAligned = (rotation - Eigen::Matrix3d::Identity()).norm() < 1e-12;
  if (axisAligned) rotation = Eigen::Matrix3d::Identity();
  worldToIndexLinear = rotation.transpose() / voxelSize;
}

std::vector<const openvdb::FloatGrid::TreeType::LeafNodeType*> FieldStorage::buildBandTable() {
  std::vector<const openvdb::FloatGrid::TreeType::LeafNodeType*> leaves;
  leaves.reserve(grid->tree().leafCount());
  for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) {
    if (!leaf->getValueMask().isOff()) leaves.push_back(leaf.getLeaf());
  }
  std::vector<LeafEntry> entries(leaves.size());
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    entries[i].origin = leaves[i]->origin();
    for (int w = 0; w < 8; ++w) {
      entries[i].mask[w] = leaves[i]->getValueMask().getWord<std::uint64_t>(w);
    }
  }
  const std::uint64_t total = band.build(std::move(entries));
  records.assign(total, BandRecord{});
  return leaves;
}

void FieldStorage::setDomain(const Eigen::AlignedBox3d& targetBounds, double padding,
                             const std::optional<Eigen::AlignedBox3d>& explicitDomain) {
  if (explicitDomain) {
    if (explicitDomain->isEmpty() || !explicitDomain->min().allFinite() ||
        !explicitDomain->max().allFinite()) {
      throw InputError("the working domain must be a non-empty finite box");
    }
    if (!explicitDomain->contains(targetBounds)) {
      throw InputError("the working domain must contain the target's bounding box");
    }
    domain = *explicitDomain;
    return;
  }
  if (!(padding >= 0.0) || !std::isfinite(padding)) {
    throw InputError("the domain padding must be a finite number >= 0");
  }
  const double pad = std::max(padding * targetBounds.sizes().maxCoeff(), voxelSize);
  domain = targetBounds;
  domain.min().array() -= pad;
  domain.max().array() += pad;
}

openvdb::MaskGrid::Ptr FieldStorage::candidateCells(int level,
                                                    const Eigen::AlignedBox3d& indexDomain,
                                                    double diagonal) const {
  const double scale = std::ldexp(1.0, level);
  auto mask = openvdb::MaskGrid::create(false);
  if (isTopLevel(coarseHalfWidth, level, diagonal)) {  // the whole domain
    const Eigen::Vector3d lo = indexDomain.min() / scale, hi = indexDomain.max() / scale;
    const openvdb::Coord a(static_cast<int>(std::floor(lo.x())),
                           static_cast<int>(std::floor(lo.y())),
                           static_cast<int>(std::floor(lo.z())));
    const openvdb::Coord b(static_cast<int>(std::ceil(hi.x())), static_cast<int>(std::ceil(hi.y())),
                           static_cast<int>(std::ceil(hi.z())));
    mask->tree().denseFill(openvdb::CoordBBox(a, b), true, true);
    return mask;
  }
  auto accessor = mask->getAccessor();
  for (const Eigen::Vector3f& footpoint : sampleFootpoints) {
    const Eigen::Vector3d c = footpoint.cast<double>() / scale;
    accessor.setValueOn(openvdb::Coord(nearestInt(c.x()), nearestInt(c.y()), nearestInt(c.z())));
  }
  const auto [cubeSteps, octahedronSteps] = dilationSteps(coarseHalfWidth + 0.5 * kSqrt3);
  openvdb::tools::dilateActiveValues(mask->tree(), octahedronSteps, openvdb::tools::NN_FACE,
                                     openvdb::tools::IGNORE_TILES);
  openvdb::tools::dilateActiveValues(mask->tree(), cubeSteps, openvdb::tools::NN_FACE_EDGE_VERTEX,
                                     openvdb::tools::IGNORE_TILES);
  return mask;
}

void FieldStorage::selectSamples() {
  // Samples: band voxels within sqrt(3)/2 voxel of the target. Every target point has a voxel
  // centre within sqrt(3)/2 voxel, which is then a sample whose footpoint is within sqrt(3)
  // voxels of that point: the bound sampleError.
  const auto& entries = band.entries();
  std::vector<std::vector<std::uint32_t>> perLeaf(entries.size());
  const double limit = 0.5 * std::sqrt(3.0) * voxelSize;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, entries.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
                        const LeafEntry& entry = entries[leaf];
                        std::uint32_t record = entry.base;
                        for (int w = 0; w < 8; ++w) {
                          const int count = countBits(entry.mask[w]);
                          for (int k = 0; k < count; ++k, ++record) {
                            if (std::abs(records[record].distance) <= limit) {
                              perLeaf[leaf].push_back(record);
                            }
                          }
                        }
                      }
                    });
  std::size_t sampleCount = 0;
  for (const auto& list : perLeaf) sampleCount += list.size();
  sampleRecords = std::vector<std::uint32_t>();  // exact capacity: statistics() counts it
  sampleRecords.reserve(sampleCount);
  sampleFootpoints.clear();
  for (const auto& list : perLeaf) {
    sampleRecords.insert(sampleRecords.end(), list.begin(), list.end());
  }
  if (sampleRecords.empty()) {
    throw InputError("the field's band holds no voxel within " +
                     std::to_string(0.5 * std::sqrt(3.0)) +
                     " voxel of the target, so the target is not resolved at this voxel size");
  }
  // Footpoints of the samples (index space): need each record's voxel.
  sampleFootpoints.resize(sampleRecords.size());
  std::vector<std::size_t> leafStart(perLeaf.size() + 1, 0);
  for (std::size_t leaf = 0; leaf < perLeaf.size(); ++leaf) {
    leafStart[leaf + 1] = leafStart[leaf] + perLeaf[leaf].size();
  }
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, entries.size(), 64),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
          const LeafEntry& entry = entries[leaf];
          std::size_t next = leafStart[leaf];
          std::uint32_t record = entry.base;
          for (int offset = 0; offset < 512 && next < leafStart[leaf + 1]; ++offset) {
            if ((entry.mask[offset >> 6] >> (offset & 63) & 1u) == 0) continue;
            if (record == sampleRecords[next]) {
              const Eigen::Vector3d centre(entry.origin.x() + (offset >> 6),
                                           entry.origin.y() + ((offset >> 3) & 7),
                                           entry.origin.z() + (offset & 7));
              const Eigen::Vector3d normal = decodeOctahedral(records[record].normal);
              sampleFootpoints[next] =
                  (centre - (records[record].distance / voxelSize) * normal).cast<float>();
              ++next;
            }
            ++record;
          }
        }
      });
  sampleError = std::sqrt(3.0) * voxelSize;
}

void FieldStorage::ensureCoarseLevels(const ProgressCallback& progress) {
  tbb::collaborative_call_once(coarseOnce, [&] {
    buildCoarseLevels(progress);
    coarseBuilt.store(true, std::memory_order_release);
  });
}

void FieldStorage::buildCoarseLevels(const ProgressCallback& progress) {
  // Levels until one band covers the whole domain.
  const Eigen::Vector3d domainMin = worldToIndex(domain.min());
  Eigen::AlignedBox3d indexDomain(domainMin);
  for (int corner = 0; corner < 8; ++corner) {
    indexDomain.extend(
        worldToIndex(domain.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner))));
  }
  const double diagonal = indexDomain.sizes().norm();
  int levelCount = 0;
  for (int level = 1; level <= kMaxCoarseLevels; ++level) {
    levelCount = level;
    if (isTopLevel(coarseHalfWidth, level, diagonal)) break;
  }

  // The candidate cells of every level need only the samples, so they are made while the
  // nearest-sample tree is built.
  std::optional<NearestPointTree> tree;
  std::vector<openvdb::MaskGrid::Ptr> masks(static_cast<std::size_t>(levelCount));
  tbb::parallel_invoke([&] { tree.emplace(sampleFootpoints); },
                       [&] {
                         tbb::parallel_for(0, levelCount, [&](int index) {
                           masks[static_cast<std::size_t>(index)] =
                               candidateCells(index + 1, indexDomain, diagonal);
                         });
                       });

  coarse.clear();
  for (int level = 1; level <= levelCount; ++level) {
    const double scale = std::ldexp(1.0, level);
    const double reach = coarseHalfWidth * scale;
    const bool top = isTopLevel(coarseHalfWidth, level, diagonal);
    const openvdb::MaskGrid& mask = *masks[static_cast<std::size_t>(level - 1)];
    std::vector<const openvdb::MaskGrid::TreeType::LeafNodeType*> leaves;
    for (auto leaf = mask.tree().cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf.getLeaf());
    std::vector<LeafEntry> levelEntries(leaves.size());
    std::vector<std::vector<std::uint32_t>> levelSamples(leaves.size());
    const CoarseLevel* finer = coarse.empty() ? nullptr : &coarse.back();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        CoarseLeafFiller filler(*tree, sampleFootpoints, band, finer, level, reach,
                                                top);
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          filler.fill(*leaves[i], levelEntries[i], levelSamples[i]);
                        }
                      });
    CoarseLevel coarseLevel;
    coarseLevel.level = level;
    std::vector<LeafEntry> kept;
    std::size_t keptCells = 0, keptLeaves = 0;
    for (const auto& list : levelSamples) {
      keptCells += list.size();
      keptLeaves += list.empty() ? 0 : 1;
    }
    coarseLevel.sampleOf.reserve(keptCells);  // exact capacities: statistics() counts them
    kept.reserve(keptLeaves);
    for (std::size_t i = 0; i < levelEntries.size(); ++i) {
      if (levelSamples[i].empty()) continue;
      kept.push_back(levelEntries[i]);
      coarseLevel.sampleOf.insert(coarseLevel.sampleOf.end(), levelSamples[i].begin(),
                                  levelSamples[i].end());
    }
    coarseLevel.table.build(std::move(kept));
    coarse.push_back(std::move(coarseLevel));
    masks[static_cast<std::size_t>(level - 1)].reset();  // mask is not used after this
    if (progress) progress("field: coarse levels", top ? 1.0 : std::min(0.99, reach / diagonal));
    if (top) break;
  }
}

}  // namespace d2vdb::detail
