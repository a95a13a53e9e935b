// A plain reference implementation of the field's surface estimator, for tests.
#pragma once

#include <vector>

#include "d2vdb/field/detail/BandLayout.h"
#include "d2vdb/field/detail/RecordCodec.h"

namespace d2vdb::test {

/// The records detail::estimateSurfaceRecords() defines (same method, same thresholds), computed
/// voxel by voxel in the most direct way: the quadric fit summed over each voxel's 27-voxel
/// stencil, the footpoint rounds of one voxel after the other with Eigen types, and the records
/// through RecordCodec::encode. Slower than the library's estimator, and written independently of
/// its optimisations (separable filters, staged rounds, fused encoding), so that tests can check
/// that those optimisations change nothing but round-off.
std::vector<detail::BandRecord> referenceSurfaceRecords(const detail::BandLayout& layout,
                                                        const detail::RecordCodec& codec);

}  // namespace d2vdb::test
