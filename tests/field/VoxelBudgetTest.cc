// Voxel budget: the estimate formula, its inverse, the refusal message, and the estimate against
// the real active voxel counts of primitive level sets.
#include "d2vdb/field/VoxelBudget.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/Primitives.h"

namespace d2vdb {
namespace {

TEST(VoxelBudget, EstimateIsFlatBandTimesSafetyFactor) {
  // 1 unit^2 at voxel size 0.1: 100 voxel faces, 6 voxels across the band, times 1.25.
  EXPECT_DOUBLE_EQ(estimateActiveVoxels(1.0, 0.1, 3.0), 100.0 * 6.0 * 1.25);
  EXPECT_DOUBLE_EQ(estimateActiveVoxels(4.0, 0.5, 1.0), 16.0 * 2.0 * 1.25);
  EXPECT_TRUE(std::isinf(estimateActiveVoxels(1.0, 0.0, 3.0)));
  const double voxel = smallestVoxelSizeWithinBudget(12.5, 3.0, 1'000'000);
  EXPECT_NEAR(estimateActiveVoxels(12.5, voxel, 3.0), 1e6, 1e-6);
}

TEST(VoxelBudget, EnforcementMessageNamesEstimateLimitAndWhatFits) {
  VoxelBudgetRequest request;
  request.subject = "the level set of a test surface";
  request.surfaceArea = 6.0;  // a unit cube
  request.voxelSize = 1e-6;   // resolution 1e6
  request.halfWidth = 3.0;
  request.longestSide = 1.0;
  request.maxActiveVoxels = 320'000'000;
  try {
    enforceVoxelBudget(request);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("the level set of a test surface"), std::string::npos) << message;
    EXPECT_NE(message.find("4.5e+13"), std::string::npos) << message;  // 6e12 * 6 * 1.25
    EXPECT_NE(message.find("3.2e+08"), std::string::npos) << message;
    // sqrt(6 * 6 * 1.25 / 3.2e8) = 3.75e-4; floor(1 / 3.75e-4) = 2666.
    EXPECT_NE(message.find("voxel size of at least 0.000375"), std::string::npos) << message;
    EXPECT_NE(message.find("resolution of at most 2666 voxels"), std::string::npos) << message;
  }
  request.voxelSize = 4e-4;  // fits
  EXPECT_NO_THROW(enforceVoxelBudget(request));
}

TEST(VoxelBudget, EstimateBoundsRealBandsFromAbove) {
  const double voxelSize = 0.05;
  const std::unique_ptr<AnalyticShape> shapes[] = {
      std::make_unique<Sphere>(Eigen::Vector3d(0, 0, 0), 1.0),
      std::make_unique<Torus>(Eigen::Vector3d(0, 0, 0), 1.0, 0.3),
      std::make_unique<Box>(Eigen::Vector3d(-1, -0.5, -0.4), Eigen::Vector3d(0.8, 0.6, 0.5)),
      std::make_unique<CappedCylinder>(Eigen::Vector3d(0, 0, 0), 0.6, 1.0)};
  for (const auto& shape : shapes) {
    for (const double halfWidth : {2.0, 3.0, 4.0}) {
      const double estimate = estimateActiveVoxels(shape->surfaceArea(), voxelSize, halfWidth);
      const auto grid = primitiveLevelSet(*shape, {voxelSize, halfWidth});
      const double actual = static_cast<double>(grid->activeVoxelCount());
      EXPECT_LE(actual, estimate) << shape->describe() << " half-width " << halfWidth;
      // The flat-band count itself is accurate to a few per cent for these shapes.
      EXPECT_GE(actual, 0.9 * estimate / kActiveVoxelSafetyFactor)
          << shape->describe() << " half-width " << halfWidth;
    }
  }
}

}  // namespace
}  // namespace d2vdb
