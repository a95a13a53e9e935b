// Voxel budget against real bands: the voxel size a budget allows gives primitive level sets
// within it, the estimate bounds real active voxel counts, and the refusal message.
#include "d2vdb/field/VoxelBudget.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/Primitives.h"

namespace d2vdb {
namespace {

// The voxel size the budget allows, against the bands it gives: a primitive level set built at
// smallestVoxelSizeWithinBudget() has at most the budgeted active voxels, and not far fewer (the
// budget is not wasted).
TEST(VoxelBudget, SmallestVoxelSizeGivesBandsWithinTheBudget) {
  const std::unique_ptr<AnalyticShape> shapes[] = {
      std::make_unique<Sphere>(Eigen::Vector3d(0, 0, 0), 1.0),
      std::make_unique<Torus>(Eigen::Vector3d(0, 0, 0), 1.0, 0.3)};
  for (const auto& shape : shapes) {
    for (const std::uint64_t budget : {20'000u, 200'000u}) {
      for (const double halfWidth : {2.0, 3.0}) {
        const double voxelSize =
            smallestVoxelSizeWithinBudget(shape->surfaceArea(), halfWidth, budget);
        const auto grid = primitiveLevelSet(*shape, {voxelSize, halfWidth});
        const double actual = static_cast<double>(grid->activeVoxelCount());
        std::printf("%s, budget %llu, half-width %g: voxel %.4g, %g active voxels (%.3f of it)\n",
                    shape->describe().c_str(), static_cast<unsigned long long>(budget), halfWidth,
                    voxelSize, actual, actual / static_cast<double>(budget));
        EXPECT_LE(actual, static_cast<double>(budget)) << shape->describe();
        EXPECT_GE(actual, 0.7 * static_cast<double>(budget)) << shape->describe();
        // A slightly smaller voxel is refused.
        VoxelBudgetRequest request;
        request.subject = shape->describe();
        request.surfaceArea = shape->surfaceArea();
        request.halfWidth = halfWidth;
        request.maxActiveVoxels = budget;
        request.voxelSize = voxelSize * 1.001;
        EXPECT_NO_THROW(enforceVoxelBudget(request));
        request.voxelSize = voxelSize * 0.99;
        EXPECT_THROW(enforceVoxelBudget(request), InputError);
      }
    }
  }
  EXPECT_TRUE(std::isinf(estimateActiveVoxels(1.0, 0.0, 3.0)));
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
