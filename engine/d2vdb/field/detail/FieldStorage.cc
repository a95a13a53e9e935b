// The assembly of a field's storage (FieldStorage.h).
#include "d2vdb/field/detail/FieldStorage.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <utility>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {
namespace {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;

bool sameBits(float a, float b) {
  std::uint32_t x = 0, y = 0;
  std::memcpy(&x, &a, sizeof x);
  std::memcpy(&y, &b, sizeof y);
  return x == y;
}

/// Whether every active value of `grid` is its record's distance, bit for bit (leaves paired with
/// the table's entries by origin).
bool gridHoldsRecordDistances(const openvdb::FloatGrid& grid, const LeafTable& table,
                              const std::vector<BandRecord>& records) {
  const auto& entries = table.entries();
  std::atomic<bool> differs{false};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, entries.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        if (differs.load(std::memory_order_relaxed)) return;
                        const LeafEntry& entry = entries[i];
                        const FloatLeaf* leaf = grid.tree().probeConstLeaf(entry.origin);
                        const float* values = leaf->buffer().data();
                        std::uint32_t record = entry.base;
                        bool same = true;
                        entry.forEachOn([&](int offset) {
                          same = same && sameBits(values[offset], records[record++].distance);
                        });
                        if (!same) {
                          differs = true;
                          return;
                        }
                      }
                    });
  return !differs;
}

/// A copy of `grid` (metadata, transform, inactive values included) whose active values are the
/// records' distances.
openvdb::FloatGrid::Ptr withRecordDistances(const openvdb::FloatGrid& grid, const LeafTable& table,
                                            const std::vector<BandRecord>& records) {
  auto copy = grid.deepCopy();
  const auto& entries = table.entries();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, entries.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const LeafEntry& entry = entries[i];
                        FloatLeaf* leaf = copy->tree().probeLeaf(entry.origin);
                        std::uint32_t record = entry.base;
                        entry.forEachOn([&](int offset) {
                          leaf->setValueOnly(static_cast<openvdb::Index>(offset),
                                             records[record++].distance);
                        });
                      }
                    });
  return copy;
}

}  // namespace

Eigen::AlignedBox3d workingDomain(const Eigen::AlignedBox3d& targetBounds, double padding,
                                  const std::optional<Eigen::AlignedBox3d>& explicitDomain,
                                  double voxelSize) {
  if (explicitDomain) {
    if (explicitDomain->isEmpty() || !explicitDomain->min().allFinite() ||
        !explicitDomain->max().allFinite()) {
      throw InputError("the working domain must be a non-empty finite box");
    }
    if (!explicitDomain->contains(targetBounds)) {
      throw InputError("the working domain must contain the target's bounding box");
    }
    return *explicitDomain;
  }
  if (!(padding >= 0.0) || !std::isfinite(padding)) {
    throw InputError("the domain padding must be a finite number >= 0");
  }
  const double pad = std::max(padding * targetBounds.sizes().maxCoeff(), voxelSize);
  Eigen::AlignedBox3d domain = targetBounds;
  domain.min().array() -= pad;
  domain.max().array() += pad;
  return domain;
}

FieldStorage::FieldStorage(const FieldDescription& description, BandLayout layout,
                           std::vector<BandRecord> records)
    : description_(description),
      layout_(std::move(layout)),
      records_(std::move(records)),
      codec_(description.kind, layout_.frame()),
      coarse_(std::max(2, description.coarseHalfWidth), description.domain, layout_.frame()) {
  if (records_.size() != layout_.voxelCount()) {
    throw RuntimeFailure("internal error: a field's records do not match its band's voxels");
  }
  if (description_.domain.isEmpty() || !description_.domain.min().allFinite() ||
      !description_.domain.max().allFinite()) {
    throw RuntimeFailure("internal error: a field's working domain is not a finite box");
  }
  if (!gridHoldsRecordDistances(*layout_.grid(), layout_.table(), records_)) {
    layout_.replaceGrid(withRecordDistances(*layout_.grid(), layout_.table(), records_));
  }
  samples_ = BandSamples::select(layout_.table(), records_, voxelSize());
}

}  // namespace d2vdb::detail
