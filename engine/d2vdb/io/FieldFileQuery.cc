// One query of a field file from a part of the file (FieldFileQuery.h).
//
// Why a part suffices, and which part. A band answer (level 0) depends on the record of the voxel
// nearest to the point only. A coarse answer at level L is the nearest band sample to the level-L
// cell c_L of the point, and level L answers because no finer level l < L kept its cell c_l, i.e.
// no sample lies within reach_l = coarseHalfWidth * 2^l (index units) of c_l (and, at level 1,
// not all 27 band voxels around 2 c_1 are active). Samples are band voxels whose |distance| is
// below sqrt(3)/2 voxel, chosen voxel by voxel, so the samples of a clipped band are exactly the
// field's samples inside the clip box, in the same relative order (ties of the nearest-sample
// search go to the lowest index, so to the same sample). The field built from the clipped
// grids therefore answers bitwise as the whole field when the box holds every voxel within
// reach_l + (cell radius) of the point for l < L and within |x - footpoint| + (cell diameter) of
// it for level L: clipped samples are a subset, so a clipped level that keeps its cell is kept by
// the whole field too, and the whole field's nearest sample lies inside the box.
#include "d2vdb/io/FieldFileQuery.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/FieldGrids.h"
#include "d2vdb/io/GridSelection.h"
#include "d2vdb/io/VdbPartialReader.h"

namespace d2vdb {
namespace {

constexpr double kHalfDiagonal = 0.8660254037844386;  // sqrt(3) / 2
/// Voxels added to every radius: the footpoint-to-voxel-centre distance of a sample (at most
/// sqrt(3)/2), the clip's rounding to voxel centres (1/2) and float rounding.
constexpr double kMargin = 2.0;

bool hasVdbExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".vdb";
}

/// The answer of a field read whole.
FieldFileAnswer answerFromWholeField(const ApproximantField& field, const Eigen::Vector3d& point) {
  ApproximantField::Accessor accessor(field);
  FieldFileAnswer result;
  result.answer = answerAt(field, accessor, point);
  if (result.answer.status != QueryStatus::Ok) {
    result.outsideMessage = outsideDomainMessage(field.domain(), point);
  }
  result.bandVoxelsRead = field.distanceGrid()->activeVoxelCount();
  return result;
}

FieldFileAnswer answerFromWholeFile(const std::filesystem::path& path, const Eigen::Vector3d& point,
                                    const LoadOptions& load) {
  return answerFromWholeField(loadInputAs<FieldInput>(path, load).field, point);
}

/// Index-space distance from `index` to the box `box` (0 inside).
double distanceToBox(const openvdb::Vec3d& index, const openvdb::CoordBBox& box) {
  const openvdb::Vec3d below = box.min().asVec3d() - index;
  const openvdb::Vec3d above = index - box.max().asVec3d();
  const openvdb::Vec3d outside(std::max({0.0, below.x(), above.x()}),
                               std::max({0.0, below.y(), above.y()}),
                               std::max({0.0, below.z(), above.z()}));
  return outside.length();
}

/// The radius (index units, about the point) of the box that makes the clipped field's answer
/// the whole field's (see the top of the file).
double requiredRadius(const FieldAnswer& answer, double voxelSize, int coarseHalfWidth) {
  const int level = answer.level;
  if (level == 0) return kHalfDiagonal + kMargin;
  const double cell = std::ldexp(1.0, level);
  // The answering level: its nearest sample lies within |x - footpoint| + |x - c_L| of c_L.
  const double toFootpoint = (answer.point - answer.approximant.footpoint).norm() / voxelSize;
  double radius = toFootpoint + 2.0 * kHalfDiagonal * cell + kMargin;
  // The finer levels: no sample within their reach of their cells.
  if (level >= 2) {
    radius = std::max(radius, (coarseHalfWidth + kHalfDiagonal) * 0.5 * cell + kMargin);
  }
  return radius;
}

/// Whether the clipped distance grid holds a band sample (an active voxel within sqrt(3)/2 voxel
/// of the target, BandSamples' rule), without which no field can be built from it.
bool holdsSample(const openvdb::FloatGrid& distance, double voxelSize) {
  const double limit = 0.5 * std::sqrt(3.0) * voxelSize;
  for (auto value = distance.cbeginValueOn(); value; ++value) {
    if (std::abs(static_cast<double>(*value)) <= limit) return true;
  }
  return false;
}

/// `companion` rebuilt on the node structure of `distance` (the clip leaves the inactive structure
/// of grids with different inactive values different: a level set keeps the nodes where inside
/// and outside meet, a companion grid prunes them), values copied leaf by leaf. False when the
/// two do not have the same active voxels (then the whole read reports the mismatch).
template <typename GridT>
bool alignTopology(openvdb::GridBase::Ptr& companion, const openvdb::FloatGrid& distance) {
  const auto typed = openvdb::gridPtrCast<GridT>(companion);
  if (!typed) return true;  // another type: fieldFromGrids() names it
  using TreeT = typename GridT::TreeType;
  if (typed->activeVoxelCount() != distance.activeVoxelCount()) return false;
  auto tree = std::make_shared<TreeT>(distance.tree(), typename TreeT::ValueType(0),
                                      openvdb::TopologyCopy());
  for (auto leaf = tree->beginLeaf(); leaf; ++leaf) {
    const auto* source = typed->tree().probeConstLeaf(leaf->origin());
    if (!source) {
      // The clip prunes a companion's leaves without active voxels (all background).
      if (!leaf->isEmpty()) return false;
      continue;
    }
    if (source->getValueMask() != leaf->getValueMask()) return false;
    leaf->buffer() = source->buffer();
  }
  auto aligned = GridT::create(tree);
  aligned->setTransform(typed->transform().copy());
  aligned->setName(typed->getName());
  for (auto meta = typed->beginMeta(); meta != typed->endMeta(); ++meta) {
    aligned->insertMeta(meta->first, *meta->second);
  }
  companion = aligned;
  return true;
}

/// alignTopology() for every grid of `grids` but the distance grid.
bool alignCompanions(openvdb::GridPtrVec& grids, const openvdb::FloatGrid::Ptr& distance) {
  for (openvdb::GridBase::Ptr& grid : grids) {
    if (grid == distance) continue;
    if (!alignTopology<openvdb::FloatGrid>(grid, *distance) ||
        !alignTopology<openvdb::Vec3SGrid>(grid, *distance) ||
        !alignTopology<openvdb::Int32Grid>(grid, *distance)) {
      return false;
    }
  }
  return true;
}

}  // namespace

FieldFileAnswer answerFromFieldFile(const std::filesystem::path& path, const Eigen::Vector3d& point,
                                    const LoadOptions& load) {
  if (!point.allFinite()) {
    throw InputError("field query: the point " + formatPoint(point, 6) + " is not finite");
  }
  if (!hasVdbExtension(path)) return answerFromWholeFile(path, point, load);
  const VdbPartialReader reader(path);
  const openvdb::GridBase::Ptr distanceMeta = findGrid(reader.metadata());
  if (!isFieldFile(reader.metadata()) || distanceMeta->type() != openvdb::FloatGrid::gridType()) {
    return answerFromWholeFile(path, point, load);  // a level set: approximants from neighbourhoods
  }
  const double voxelSize = distanceMeta->voxelSize()[0];
  // The stored working domain (fieldFromGrids() keeps it exactly): a point outside needs no read.
  Eigen::AlignedBox3d domain;
  try {
    const openvdb::Vec3d lo = distanceMeta->metaValue<openvdb::Vec3d>(kFieldDomainMinMetadata);
    const openvdb::Vec3d hi = distanceMeta->metaValue<openvdb::Vec3d>(kFieldDomainMaxMetadata);
    domain = Eigen::AlignedBox3d(Eigen::Vector3d(lo.x(), lo.y(), lo.z()),
                                 Eigen::Vector3d(hi.x(), hi.y(), hi.z()));
  } catch (const openvdb::Exception&) {
    return answerFromWholeFile(path, point, load);  // the whole read names what is missing
  }
  if (domain.isEmpty() || !domain.min().allFinite() || !domain.max().allFinite()) {
    return answerFromWholeFile(path, point, load);
  }
  if (!domain.contains(point)) {
    FieldFileAnswer outside;
    outside.answer.point = point;
    outside.answer.status = QueryStatus::OutsideDomain;
    outside.outsideMessage = outsideDomainMessage(domain, point);
    outside.partial = true;
    return outside;
  }
  // The band's index bounding box (written by OpenVDB with every grid): a clip box that covers it
  // reads the whole band.
  openvdb::CoordBBox bandBox;
  try {
    bandBox = openvdb::CoordBBox(
        openvdb::Coord(distanceMeta->metaValue<openvdb::Vec3i>("file_bbox_min")),
        openvdb::Coord(distanceMeta->metaValue<openvdb::Vec3i>("file_bbox_max")));
  } catch (const openvdb::Exception&) {
    return answerFromWholeFile(path, point, load);
  }
  const openvdb::Vec3d index =
      distanceMeta->transform().worldToIndex(openvdb::Vec3d(point.x(), point.y(), point.z()));
  const int coarseHalfWidth = std::max(2, load.field.coarseHalfWidth);
  FieldFileAnswer result;
  // Voxels: the band's half-width is a few voxels, and no sample lies nearer than the band's box.
  double radius = 3.0 * kMargin + 8.0 + distanceToBox(index, bandBox);
  bool wholeBand = false;  // the clip would cover most of the band
  for (int attempt = 0; attempt < 64; ++attempt) {
    const openvdb::CoordBBox clip(openvdb::Coord::floor(index - openvdb::Vec3d(radius)),
                                  openvdb::Coord::ceil(index + openvdb::Vec3d(radius)));
    // A box that holds most of the band costs more than reading it whole.
    const openvdb::CoordBBox overlap = [&] {
      openvdb::CoordBBox box = clip;
      box.intersect(bandBox);
      return box;
    }();
    if (clip.isInside(bandBox) || (!overlap.empty() && overlap.volume() > bandBox.volume() / 2)) {
      wholeBand = true;
      break;
    }
    const openvdb::BBoxd worldBox(distanceMeta->transform().indexToWorld(clip.min().asVec3d()),
                                  distanceMeta->transform().indexToWorld(clip.max().asVec3d()));
    openvdb::GridPtrVec grids = reader.read(worldBox);
    ++result.reads;
    const auto distance = openvdb::gridPtrCast<openvdb::FloatGrid>(findGrid(grids));
    if (!distance || !holdsSample(*distance, voxelSize)) {
      radius *= 4.0;  // no target nearby: look further
      continue;
    }
    if (!alignCompanions(grids, distance)) break;  // mismatched grids: the whole read says how
    ApproximantFieldOptions options = load.field;
    const ApproximantField field = fieldFromGrids(grids, path.string(), options);
    ApproximantField::Accessor accessor(field);
    result.answer = answerAt(field, accessor, point);
    if (result.answer.status != QueryStatus::Ok) {
      result.outsideMessage = outsideDomainMessage(field.domain(), point);
      result.partial = true;
      return result;
    }
    const double needed = requiredRadius(result.answer, voxelSize, coarseHalfWidth);
    if (needed <= radius) {
      result.partial = true;
      result.bandVoxelsRead = distance->activeVoxelCount();
      return result;
    }
    radius = std::max(needed, 1.5 * radius);
  }
  const int reads = result.reads;
  // Most of the band is needed: read it whole from the file already checked and mapped. Other
  // endings (mismatched grids) go through the whole-file read, whose messages name the fault.
  result = wholeBand ? answerFromWholeField(
                           fieldFromGrids(reader.readAll(), path.string(), load.field), point)
                     : answerFromWholeFile(path, point, load);
  result.reads = reads;
  return result;
}

}  // namespace d2vdb
