// Approximant fields as standard OpenVDB grids and back (FieldGrids.h).
#include "d2vdb/io/FieldGrids.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/FieldBand.h"
#include "d2vdb/field/MeshToLevelSet.h"

namespace d2vdb {
namespace {

openvdb::Vec3s toVec(const Eigen::Vector3d& v) {
  return openvdb::Vec3s(static_cast<float>(v.x()), static_cast<float>(v.y()),
                        static_cast<float>(v.z()));
}

Eigen::Vector3d fromVec(const openvdb::Vec3s& v) {
  return Eigen::Vector3d(v.x(), v.y(), v.z());
}

/// The field format whose "flags" grid was Int32 (read, never written).
constexpr int kInt32FlagsVersion = 1;

// Every flag bit must survive a float, and a half float (whole numbers are exact below 2048).
static_assert(kFlagCutLocus < 2048 && kFlagCurvatureClamped < 2048 &&
                  kFlagDegradedEstimate < 2048 && kFlagFarField < 2048 && kFlagEndPoint < 2048,
              "ApproximantFlag bits beyond 2^10 would not survive the half-float flags grid");

void setFieldMetadata(openvdb::GridBase& grid, const ApproximantField& field) {
  grid.insertMeta(kFieldKindMetadata, openvdb::StringMetadata(targetKindName(field.kind())));
  grid.insertMeta(kFieldEstimatorMetadata, openvdb::StringMetadata(field.estimator()));
  grid.insertMeta(kFieldVersionMetadata, openvdb::Int32Metadata(kFieldFormatVersion));
  grid.insertMeta(
      kDistanceKindMetadata,
      openvdb::StringMetadata(field.kind() == TargetKind::Surface ? "signed" : "unsigned"));
  const auto toVec3d = [](const Eigen::Vector3d& v) { return openvdb::Vec3d(v.x(), v.y(), v.z()); };
  grid.insertMeta(kFieldDomainMinMetadata, openvdb::Vec3DMetadata(toVec3d(field.domain().min())));
  grid.insertMeta(kFieldDomainMaxMetadata, openvdb::Vec3DMetadata(toVec3d(field.domain().max())));
}

/// A grid of `GridT` with the distance grid's transform and active topology, values zero.
template <typename GridT>
typename GridT::Ptr companionGrid(const openvdb::FloatGrid& distance, const std::string& name) {
  using TreeT = typename GridT::TreeType;
  auto grid = GridT::create(typename TreeT::Ptr(
      new TreeT(distance.tree(), typename TreeT::ValueType(0), openvdb::TopologyCopy())));
  grid->setTransform(distance.transform().copy());
  grid->setName(name);
  return grid;
}

/// The companion grids of one kind of field: the flags, and per kind up to three vector and two
/// scalar grids (null where the kind has none).
struct Companions {
  openvdb::FloatGrid::Ptr flags;  ///< the ApproximantFlag bits as whole numbers
  openvdb::Vec3SGrid::Ptr vector0, vector1, vector2;
  openvdb::FloatGrid::Ptr scalar0, scalar1;
};

/// The float grid carrying the field metadata, or null.
openvdb::FloatGrid::Ptr fieldDistanceGrid(const openvdb::GridPtrVec& grids) {
  for (const auto& grid : grids) {
    auto floatGrid = openvdb::gridPtrCast<openvdb::FloatGrid>(grid);
    if (floatGrid && (*floatGrid)[kFieldKindMetadata]) return floatGrid;
  }
  return nullptr;
}

/// The first float level set of `grids`, or null.
openvdb::FloatGrid::Ptr firstLevelSet(const openvdb::GridPtrVec& grids) {
  for (const auto& grid : grids) {
    auto floatGrid = openvdb::gridPtrCast<openvdb::FloatGrid>(grid);
    if (floatGrid && floatGrid->getGridClass() == openvdb::GRID_LEVEL_SET) return floatGrid;
  }
  return nullptr;
}

/// What a stored field's metadata says.
struct StoredField {
  int version = kFieldFormatVersion;
  std::string kindName;
  TargetKind kind = TargetKind::Surface;
  std::string estimator;
  Eigen::AlignedBox3d domain;
};

/// The target kind named `kindName` in a stored field; InputError for an unknown name.
TargetKind storedKind(const std::string& kindName, const std::string& source) {
  if (kindName == "surface") return TargetKind::Surface;
  if (kindName == "curve") return TargetKind::Curve;
  if (kindName == "points") return TargetKind::Points;
  throw InputError(source + ": unknown field kind '" + kindName + "'");
}

/// Reads and checks the field metadata of `distance` (format version, kind, estimator, working
/// domain) and that its band is a non-empty set of voxels. InputError naming `source` otherwise.
StoredField readStoredField(const openvdb::FloatGrid& distance, const std::string& source) {
  StoredField stored;
  int version = 0;
  try {
    stored.kindName = distance.metaValue<std::string>(kFieldKindMetadata);
    version = distance.metaValue<openvdb::Int32>(kFieldVersionMetadata);
  } catch (const openvdb::Exception&) {
    throw InputError(source + ": the field's metadata (" + std::string(kFieldVersionMetadata) +
                     ") is missing or has the wrong type");
  }
  if (version != kFieldFormatVersion && version != kInt32FlagsVersion) {
    throw InputError(source + ": field format version " + std::to_string(version) +
                     " is not supported (this d2vdb reads versions " +
                     std::to_string(kInt32FlagsVersion) + " and " +
                     std::to_string(kFieldFormatVersion) + ")");
  }
  stored.version = version;
  stored.kind = storedKind(stored.kindName, source);
  try {
    stored.estimator = distance.metaValue<std::string>(kFieldEstimatorMetadata);
    const openvdb::Vec3d lo = distance.metaValue<openvdb::Vec3d>(kFieldDomainMinMetadata);
    const openvdb::Vec3d hi = distance.metaValue<openvdb::Vec3d>(kFieldDomainMaxMetadata);
    stored.domain = Eigen::AlignedBox3d(Eigen::Vector3d(lo.x(), lo.y(), lo.z()),
                                        Eigen::Vector3d(hi.x(), hi.y(), hi.z()));
  } catch (const openvdb::Exception&) {
    throw InputError(source + ": the field's estimator or domain metadata is missing");
  }
  const Eigen::AlignedBox3d& domain = stored.domain;
  if (domain.isEmpty() || !domain.min().allFinite() || !domain.max().allFinite()) {
    throw InputError(source + ": the field's working domain metadata is not a finite box");
  }
  if (distance.activeVoxelCount() == 0) throw InputError(source + ": the field's band is empty");
  if (distance.tree().hasActiveTiles()) {
    throw InputError(source +
                     ": the field's distance grid has active tiles (not a field d2vdb "
                     "wrote)");
  }
  return stored;
}

/// The companion grid `name` of a stored `kindName` field, of type GridT, with the distance
/// grid's active voxels and transform; InputError naming `source` otherwise.
template <typename GridT>
typename GridT::Ptr storedCompanion(const openvdb::GridPtrVec& grids, const std::string& name,
                                    const openvdb::FloatGrid& distance, const std::string& kindName,
                                    const std::string& source) {
  openvdb::GridBase::Ptr grid;
  for (const auto& candidate : grids) {
    if (candidate && candidate->getName() == name) {
      grid = candidate;
      break;
    }
  }
  if (!grid) {
    throw InputError(source + ": the " + kindName + " field's companion grid '" + name +
                     "' is missing");
  }
  auto typed = openvdb::gridPtrCast<GridT>(grid);
  if (!typed) {
    throw InputError(source + ": the companion grid '" + name + "' holds " + grid->valueType() +
                     " values, expected " + GridT::gridType());
  }
  if (!typed->tree().hasSameTopology(distance.tree())) {
    throw InputError(source + ": the companion grid '" + name +
                     "' does not share the distance grid's active voxels");
  }
  if (typed->transform() != distance.transform()) {
    throw InputError(source + ": the companion grid '" + name +
                     "' has a different transform from the distance grid");
  }
  return typed;
}

/// The flags of a stored field as whole numbers in a float grid: version 1 files hold them as
/// Int32 and are converted. InputError naming `source` for a flags value that is not a whole
/// number in [0, 65535] (the ApproximantFlag bits fit 16 bits).
openvdb::FloatGrid::Ptr storedFlags(const openvdb::GridPtrVec& grids,
                                    const openvdb::FloatGrid& distance, const StoredField& stored,
                                    const std::string& source) {
  openvdb::FloatGrid::Ptr flags;
  bool valid = true;
  if (stored.version == kInt32FlagsVersion) {
    const openvdb::Int32Grid::Ptr old =
        storedCompanion<openvdb::Int32Grid>(grids, "flags", distance, stored.kindName, source);
    flags = companionGrid<openvdb::FloatGrid>(distance, "flags");
    openvdb::FloatGrid::Accessor converted = flags->getAccessor();
    for (auto value = old->cbeginValueOn(); value && valid; ++value) {
      valid = *value >= 0 && *value <= 0xffff;
      converted.setValueOnly(value.getCoord(), static_cast<float>(*value));
    }
  } else {
    flags = storedCompanion<openvdb::FloatGrid>(grids, "flags", distance, stored.kindName, source);
    for (auto value = flags->cbeginValueOn(); value && valid; ++value) {
      valid = *value >= 0.0f && *value <= 65535.0f && std::floor(*value) == *value;
    }
  }
  if (!valid) {
    throw InputError(source +
                     ": the companion grid 'flags' holds a value that is not a set of "
                     "field flags (a whole number from 0 to 65535)");
  }
  return flags;
}

/// The companion grids a stored field of `stored.kind` must have (see fieldToGrids()).
Companions storedCompanions(const openvdb::GridPtrVec& grids, const openvdb::FloatGrid& distance,
                            const StoredField& stored, const std::string& source) {
  const auto vectors = [&](const std::string& name) {
    return storedCompanion<openvdb::Vec3SGrid>(grids, name, distance, stored.kindName, source);
  };
  const auto scalars = [&](const std::string& name) {
    return storedCompanion<openvdb::FloatGrid>(grids, name, distance, stored.kindName, source);
  };
  Companions c;
  c.flags = storedFlags(grids, distance, stored, source);
  if (stored.kind == TargetKind::Surface) {
    c.vector0 = vectors("normal");
    c.scalar0 = scalars("k1");
    c.scalar1 = scalars("k2");
    c.vector1 = vectors("e1");
  } else if (stored.kind == TargetKind::Curve) {
    c.vector0 = vectors("direction");
    c.vector1 = vectors("tangent");
    c.scalar0 = scalars("curvature");
    c.vector2 = vectors("principal_normal");
  } else {
    c.vector0 = vectors("direction");
  }
  return c;
}

/// A factory of per-worker functions that read each voxel's approximant from the companion grids
/// at the same coordinates (each with its own accessors). `c` and `source` must outlive it.
auto storedApproximants(const Companions& c, const openvdb::FloatGrid::Ptr& distance,
                        TargetKind kind, const std::string& source) {
  return [&c, distance, kind, &source]() -> FieldBand::VoxelApproximant {
    const auto vectorReader = [](const openvdb::Vec3SGrid::Ptr& grid) {
      return grid ? std::optional<openvdb::Vec3SGrid::ConstAccessor>(grid->getConstAccessor())
                  : std::nullopt;
    };
    const auto scalarReader = [](const openvdb::FloatGrid::Ptr& grid) {
      return grid ? std::optional<openvdb::FloatGrid::ConstAccessor>(grid->getConstAccessor())
                  : std::nullopt;
    };
    return
        [d = distance->getConstAccessor(), flags = c.flags->getConstAccessor(),
         v0 = c.vector0->getConstAccessor(), v1 = vectorReader(c.vector1),
         v2 = vectorReader(c.vector2), f0 = scalarReader(c.scalar0), f1 = scalarReader(c.scalar1),
         kind, &source](const openvdb::Coord& ijk, const Eigen::Vector3d&) {
          Approximant a;
          a.kind = kind;
          a.distance = d.getValue(ijk);
          a.flags = static_cast<std::uint16_t>(flags.getValue(ijk));
          a.normal = fromVec(v0.getValue(ijk));
          if (v1) a.tangent = fromVec(v1->getValue(ijk));
          if (v2) a.principalNormal = fromVec(v2->getValue(ijk));
          if (f0) a.k1 = f0->getValue(ijk);
          if (f1) a.k2 = f1->getValue(ijk);
          if (!std::isfinite(a.distance) || !(std::abs(a.normal.norm() - 1.0) < 1e-3) ||
              !a.tangent.allFinite() || !std::isfinite(a.k1) || !std::isfinite(a.k2) ||
              !a.principalNormal.allFinite()) {
            throw InputError(source +
                             ": the field's companion grids hold non-finite values or normals "
                             "that are not unit vectors");
          }
          return a;
        };
  };
}

/// Empty companion grids (zero values, the band's active voxels) for a field of `kind` with
/// distance grid `band`.
Companions newCompanions(const openvdb::FloatGrid& band, TargetKind kind) {
  const auto vectorGrid = [&](const std::string& name) {
    auto grid = companionGrid<openvdb::Vec3SGrid>(band, name);
    grid->setVectorType(openvdb::VEC_INVARIANT);
    return grid;
  };
  Companions c;
  c.flags = companionGrid<openvdb::FloatGrid>(band, "flags");
  if (kind == TargetKind::Surface) {
    c.vector0 = vectorGrid("normal");
    c.scalar0 = companionGrid<openvdb::FloatGrid>(band, "k1");
    c.scalar1 = companionGrid<openvdb::FloatGrid>(band, "k2");
    c.vector1 = vectorGrid("e1");
  } else if (kind == TargetKind::Curve) {
    c.vector0 = vectorGrid("direction");
    c.vector1 = vectorGrid("tangent");
    c.scalar0 = companionGrid<openvdb::FloatGrid>(band, "curvature");
    c.vector2 = vectorGrid("principal_normal");
  } else {
    c.vector0 = vectorGrid("direction");
  }
  return c;
}

/// Writes every band voxel's approximant into the companion grids.
void fillCompanions(const ApproximantField& field, const Companions& c) {
  const TargetKind kind = field.kind();
  // Leaf by leaf of the flags grid; every other companion's leaf is the one with the same origin.
  std::vector<openvdb::FloatTree::LeafNodeType*> leaves;
  leaves.reserve(c.flags->tree().leafCount());
  for (auto leaf = c.flags->tree().beginLeaf(); leaf; ++leaf) leaves.push_back(leaf.getLeaf());
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, leaves.size(), 16),
      [&](const tbb::blocked_range<std::size_t>& range) {
        ApproximantField::Accessor accessor(field);
        const auto leafOf = [](const auto& grid, const openvdb::Coord& origin) {
          return grid ? grid->tree().probeLeaf(origin) : nullptr;
        };
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          auto& flags = *leaves[i];
          const openvdb::Coord origin = flags.origin();
          auto* v0 = leafOf(c.vector0, origin);
          auto* v1 = leafOf(c.vector1, origin);
          auto* v2 = leafOf(c.vector2, origin);
          auto* f0 = leafOf(c.scalar0, origin);
          auto* f1 = leafOf(c.scalar1, origin);
          for (auto on = flags.getValueMask().beginOn(); on; ++on) {
            const openvdb::Index offset = on.pos();
            const std::optional<Approximant> a =
                accessor.bandApproximant(flags.offsetToGlobalCoord(offset));
            if (!a) throw RuntimeFailure("internal error: a field's grid and band disagree");
            flags.setValueOnly(offset, static_cast<float>(a->flags));
            v0->setValueOnly(offset, toVec(a->normal));
            if (kind == TargetKind::Surface) {
              f0->setValueOnly(offset, static_cast<float>(a->k1));
              f1->setValueOnly(offset, static_cast<float>(a->k2));
              v1->setValueOnly(offset, toVec(a->tangent));
            } else if (kind == TargetKind::Curve) {
              v1->setValueOnly(offset, toVec(a->tangent));
              f0->setValueOnly(offset, static_cast<float>(a->k1));
              v2->setValueOnly(offset, toVec(a->principalNormal));
            }
          }
        }
      });
}

}  // namespace

openvdb::GridPtrVec fieldToGrids(const ApproximantField& field) {
  const TargetKind kind = field.kind();
  // A shallow copy: shares the tree, owns its metadata.
  auto distanceGrid = openvdb::ConstPtrCast<openvdb::FloatGrid>(field.distanceGrid())->copy();
  if (distanceGrid->getName().empty()) {
    distanceGrid->setName(kind == TargetKind::Surface ? "surface" : "unsigned_distance");
  }
  setFieldMetadata(*distanceGrid, field);

  const Companions c = newCompanions(*field.distanceGrid(), kind);
  fillCompanions(field, c);

  openvdb::GridPtrVec grids{distanceGrid};
  for (const openvdb::GridBase::Ptr& grid :
       {openvdb::GridBase::Ptr(c.vector0), openvdb::GridBase::Ptr(c.vector1),
        openvdb::GridBase::Ptr(c.vector2), openvdb::GridBase::Ptr(c.scalar0),
        openvdb::GridBase::Ptr(c.scalar1)}) {
    if (grid) grids.push_back(grid);
  }
  grids.push_back(c.flags);
  return grids;
}

ApproximantField fieldFromGrids(const openvdb::GridPtrVec& grids, const std::string& source,
                                const ApproximantFieldOptions& options,
                                const ProgressCallback& progress) {
  const openvdb::FloatGrid::Ptr distance = fieldDistanceGrid(grids);
  if (!distance) {
    // A level set alone (e.g. from another tool): compute the approximants now.
    if (openvdb::FloatGrid::Ptr levelSet = firstLevelSet(grids)) {
      return ApproximantField::fromLevelSet(levelSet, options, progress);
    }
    throw InputError(source + " holds neither an approximant field nor a float level set");
  }
  const StoredField stored = readStoredField(*distance, source);
  const Companions c = storedCompanions(grids, *distance, stored, source);
  FieldBand band = FieldBand::activeVoxelsOf(stored.kind, distance);
  band.setApproximantsPerWorker(storedApproximants(c, distance, stored.kind, source))
      .setEstimator(stored.estimator)
      .setLabel(source)
      .setTargetBounds(stored.domain);
  ApproximantFieldOptions fieldOptions = options;
  fieldOptions.domain = stored.domain;  // the stored field's working domain, exactly
  return ApproximantField::fromBand(band, fieldOptions, progress);
}

}  // namespace d2vdb
