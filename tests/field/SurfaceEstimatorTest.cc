// The library's surface estimator (separable quadric fits, staged footpoint rounds, fused record
// encoding) against the plain reference implementation of the same method
// (SurfaceEstimatorReference.h), record by record, on analytic level sets and on meshes' level
// sets.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "FieldTestSupport.h"
#include "SurfaceEstimatorReference.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/field/detail/SurfaceEstimator.h"
#include "d2vdb/mesh/MeshIO.h"

namespace d2vdb {
namespace {

using detail::BandLayout;
using detail::BandRecord;
using detail::RecordCodec;

/// Distance between two floats in units in the last place (same sign assumed by the caller).
std::int64_t floatUlps(float a, float b) {
  std::int32_t ia, ib;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  if ((ia < 0) != (ib < 0)) return a == b ? 0 : std::numeric_limits<std::int64_t>::max();
  return std::abs(static_cast<std::int64_t>(ia) - ib);
}

/// Differences between two record sets of the same band.
struct RecordDifferences {
  std::size_t records = 0, identical = 0, flags = 0;
  std::size_t cutLocus = 0, degraded = 0, clamped = 0;  ///< flagged records of the first set
  std::int64_t distanceUlps = 0, normalSteps = 0, angleSteps = 0, curvatureUlps = 0;
};

RecordDifferences compare(const std::vector<BandRecord>& a, const std::vector<BandRecord>& b) {
  RecordDifferences diff;
  diff.records = a.size();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const BandRecord &x = a[i], &y = b[i];
    if (x.flags & kFlagCutLocus) ++diff.cutLocus;
    if (x.flags & kFlagDegradedEstimate) ++diff.degraded;
    if (x.flags & kFlagCurvatureClamped) ++diff.clamped;
    if (std::memcmp(&x, &y, sizeof x) == 0) {
      ++diff.identical;
      continue;
    }
    if (x.flags != y.flags) ++diff.flags;
    diff.distanceUlps = std::max(diff.distanceUlps, floatUlps(x.distance, y.distance));
    for (int k = 0; k < 2; ++k) {
      diff.normalSteps =
          std::max<std::int64_t>(diff.normalSteps, std::abs(x.normal[k] - y.normal[k]));
    }
    const int angle = std::abs(int{x.angle} - int{y.angle});
    diff.angleSteps = std::max<std::int64_t>(diff.angleSteps, std::min(angle, 65536 - angle));
    diff.curvatureUlps = std::max<std::int64_t>(
        {diff.curvatureUlps, std::abs(int{x.c0} - int{y.c0}), std::abs(int{x.c1} - int{y.c1})});
  }
  return diff;
}

RecordDifferences compareWithReference(const openvdb::FloatGrid::Ptr& grid, const char* name) {
  const BandLayout layout(grid, name);
  const RecordCodec codec(TargetKind::Surface, layout.frame());
  const auto fast = detail::estimateSurfaceRecords(layout, codec, {});
  const auto reference = test::referenceSurfaceRecords(layout, codec);
  EXPECT_EQ(fast.size(), reference.size());
  const RecordDifferences diff = compare(fast, reference);
  std::printf(
      "%s: %zu records (%zu cut locus, %zu degraded, %zu clamped), %zu identical; differing: %zu "
      "flags, distance %lld ulp, normal %lld, angle %lld, curvature %lld half ulp\n",
      name, diff.records, diff.cutLocus, diff.degraded, diff.clamped, diff.identical, diff.flags,
      static_cast<long long>(diff.distanceUlps), static_cast<long long>(diff.normalSteps),
      static_cast<long long>(diff.angleSteps), static_cast<long long>(diff.curvatureUlps));
  // Same method, same operations in the same order: the same bits, record for record.
  EXPECT_EQ(diff.identical, diff.records);
  return diff;
}

TEST(SurfaceEstimator, SameRecordsAsTheReferenceOnASphere) {
  const Sphere sphere(Eigen::Vector3d(0.1, -0.2, 0.05), 1.0);
  compareWithReference(primitiveLevelSet(sphere, {0.025, 3.0}), "sphere");
}

// A band of 12 voxels: footpoints up to 12 voxels from their voxels, beyond the leaves whose fits
// the estimator keeps at hand, so that it fits their leaves again on demand.
TEST(SurfaceEstimator, SameRecordsAsTheReferenceOnAWideBand) {
  const Sphere sphere(Eigen::Vector3d(0.013, -0.02, 0.005), 0.5);
  compareWithReference(primitiveLevelSet(sphere, {0.025, 12.0}), "wide band");
}

// Sharp edges and corners: cut loci inside, where the estimator falls back to the local gradient.
TEST(SurfaceEstimator, SameRecordsAsTheReferenceOnABox) {
  const Box box(Eigen::Vector3d(-0.3, -0.2, -0.05), Eigen::Vector3d(0.4, 0.25, 0.08));
  compareWithReference(primitiveLevelSet(box, {0.01, 3.0}), "box");
}

// A scanned mesh's level set: kinks, thin parts, cut loci, degraded and clamped estimates.
TEST(SurfaceEstimator, SameRecordsAsTheReferenceOnTheBunny) {
  const TriangleMesh mesh =
      readMesh(std::filesystem::path(D2VDB_SOURCE_DIR) / "volumes" / "bunny.obj");
  LevelSetOptions options;
  options.resolution = 96;
  compareWithReference(meshToLevelSet(mesh, options).grid, "bunny");
}

}  // namespace
}  // namespace d2vdb
