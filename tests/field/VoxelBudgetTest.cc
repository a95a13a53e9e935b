// Voxel budget: the estimate against the active voxel counts of real level sets (primitives and
// meshes, narrow and wide bands, one and several pieces), the voxel size a budget allows against
// the bands it gives, the advice of the refusal message, and refusal before anything is allocated.
#include "d2vdb/field/VoxelBudget.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/field/Primitives.h"
#include "field/FieldTestSupport.h"

namespace d2vdb {
namespace {

// An axis-aligned box mesh of 12 triangles, outward facing.
TriangleMesh boxMesh(const Eigen::Vector3f& low, const Eigen::Vector3f& high) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.positions.emplace_back(i & 1 ? high.x() : low.x(), i & 2 ? high.y() : low.y(),
                                i & 4 ? high.z() : low.z());
  }
  const TriangleMesh::Triangle faces[] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                          {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                          {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& face : faces) mesh.triangles.push_back(face);
  return mesh;
}

TriangleMesh merged(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh mesh = a;
  const auto offset = static_cast<TriangleMesh::Index>(a.positions.size());
  mesh.positions.insert(mesh.positions.end(), b.positions.begin(), b.positions.end());
  for (TriangleMesh::Triangle t : b.triangles) {
    for (auto& index : t) index += offset;
    mesh.triangles.push_back(t);
  }
  return mesh;
}

VoxelBudgetRequest meshRequest(const TriangleMesh& mesh, double voxelSize, double halfWidth) {
  VoxelBudgetRequest request;
  request.subject = "test mesh";
  const std::vector<SurfacePiece> pieces = surfacePieces(mesh);
  Eigen::AlignedBox3d box;
  for (const auto& p : mesh.positions) box.extend(p.cast<double>());
  request.boxSides = {box.sizes().x(), box.sizes().y(), box.sizes().z()};
  request.pieces = pieces;
  request.voxelSize = voxelSize;
  request.halfWidth = halfWidth;
  request.longestSide = box.sizes().maxCoeff();
  return request;
}

// The estimate must bound the real count from above (it protects memory) and stay within a small
// factor of it (it must not refuse what fits). Measured: 1.04 to 1.84 times the real count over
// the cases below.
void expectEstimateBrackets(double estimate, double actual, const std::string& what) {
  EXPECT_LE(actual, estimate) << what;
  EXPECT_LE(estimate, 2.0 * actual) << what << ": estimate " << estimate << ", actual " << actual;
}

TEST(VoxelBudget, EstimateBracketsPrimitiveBandsNarrowAndWide) {
  const double voxelSize = 0.1;
  const std::unique_ptr<AnalyticShape> shapes[] = {
      std::make_unique<Sphere>(Eigen::Vector3d(0, 0, 0), 1.0),
      std::make_unique<Torus>(Eigen::Vector3d(0, 0, 0), 1.0, 0.3),
      std::make_unique<Box>(Eigen::Vector3d(-1, -0.5, -0.4), Eigen::Vector3d(0.8, 0.6, 0.5)),
      std::make_unique<CappedCylinder>(Eigen::Vector3d(0, 0, 0), 0.6, 1.0)};
  for (const auto& shape : shapes) {
    for (const double halfWidth : {2.0, 3.0, 6.0, 15.0, 30.0}) {
      VoxelBudgetRequest request;
      request.surfaceArea = shape->surfaceArea();
      const Eigen::Vector3d sides = shape->bounds().sizes();
      request.boxSides = {sides.x(), sides.y(), sides.z()};
      request.voxelSize = voxelSize;
      request.halfWidth = halfWidth;
      const auto grid = primitiveLevelSet(*shape, {voxelSize, halfWidth});
      expectEstimateBrackets(estimateActiveVoxels(request),
                             static_cast<double>(grid->activeVoxelCount()),
                             shape->describe() + " half-width " + std::to_string(halfWidth));
    }
  }
}

// The voxel size the budget allows, against the bands it gives: a primitive level set built at
// smallestVoxelSizeWithinBudget() has at most the budgeted active voxels, and not far fewer (the
// budget is not wasted: the estimate stays within 2x of real counts, as above).
TEST(VoxelBudget, SmallestVoxelSizeGivesBandsWithinTheBudget) {
  const std::unique_ptr<AnalyticShape> shapes[] = {
      std::make_unique<Sphere>(Eigen::Vector3d(0, 0, 0), 1.0),
      std::make_unique<Torus>(Eigen::Vector3d(0, 0, 0), 1.0, 0.3)};
  for (const auto& shape : shapes) {
    for (const std::uint64_t budget : {20'000u, 200'000u}) {
      for (const double halfWidth : {2.0, 3.0}) {
        VoxelBudgetRequest request;
        request.subject = shape->describe();
        request.surfaceArea = shape->surfaceArea();
        const Eigen::Vector3d sides = shape->bounds().sizes();
        request.boxSides = {sides.x(), sides.y(), sides.z()};
        request.halfWidth = halfWidth;
        request.maxActiveVoxels = budget;
        const double voxelSize = smallestVoxelSizeWithinBudget(request);
        const auto grid = primitiveLevelSet(*shape, {voxelSize, halfWidth});
        const double actual = static_cast<double>(grid->activeVoxelCount());
        std::printf("%s, budget %llu, half-width %g: voxel %.4g, %g active voxels (%.3f of it)\n",
                    shape->describe().c_str(), static_cast<unsigned long long>(budget), halfWidth,
                    voxelSize, actual, actual / static_cast<double>(budget));
        EXPECT_LE(actual, static_cast<double>(budget)) << shape->describe();
        EXPECT_GE(actual, 0.5 * static_cast<double>(budget)) << shape->describe();
        // A slightly larger voxel is accepted, a slightly smaller one refused.
        request.voxelSize = voxelSize * 1.001;
        EXPECT_NO_THROW(enforceVoxelBudget(request));
        request.voxelSize = voxelSize * 0.99;
        EXPECT_THROW(enforceVoxelBudget(request), InputError);
      }
    }
  }
}

TEST(VoxelBudget, EstimateBracketsMeshBandsOfOneAndSeveralPieces) {
  const TriangleMesh cube = boxMesh({0, 0, 0}, {1, 1, 1});
  const TriangleMesh plate = boxMesh({0, 0, 0}, {2, 1.5f, 0.05f});
  // Two cubes far apart: a wide band around each, not around the box holding both.
  const TriangleMesh pair = merged(cube, boxMesh({7, 0, 0}, {8, 1, 1}));
  ASSERT_EQ(surfacePieces(pair).size(), 2u);
  EXPECT_NEAR(surfacePieces(pair)[1].area, 6.0, 1e-9);
  EXPECT_NEAR(surfacePieces(pair)[1].boxSides[0], 1.0, 1e-6);
  const TriangleMesh sphere = test::makeIcosphere({0, 0, 0}, 1.0, 3);
  struct Case {
    const char* name;
    const TriangleMesh* mesh;
  };
  for (const Case& c : {Case{"cube", &cube}, Case{"plate", &plate}, Case{"two cubes", &pair},
                        Case{"icosphere", &sphere}}) {
    for (const double halfWidth : {1.0, 3.0, 12.0}) {
      LevelSetOptions options;
      options.voxelSize = 0.125;
      options.halfWidth = halfWidth;
      const LevelSetResult result = meshToLevelSet(*c.mesh, options);
      expectEstimateBrackets(estimateActiveVoxels(meshRequest(*c.mesh, 0.125, halfWidth)),
                             static_cast<double>(result.grid->activeVoxelCount()),
                             std::string(c.name) + " half-width " + std::to_string(halfWidth));
    }
  }
}

TEST(VoxelBudget, WideBandOnATinyMeshIsRefusedBeforeAllocating) {
  // mesh2sdf --resolution 200 --half-width 1000 on a 12-triangle cube: about 4e9 voxels at any
  // voxel size; this used to be estimated at 1.5e7 and die of std::bad_alloc.
  const TriangleMesh cube = boxMesh({0, 0, 0}, {1, 1, 1});
  LevelSetOptions options;
  options.resolution = 200;
  options.halfWidth = 1000;
  try {
    meshToLevelSet(cube, options);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("no voxel size fits"), std::string::npos) << message;
    // (4/3 pi 1000^3) * 1.25 = 5.24e9.
    EXPECT_NE(message.find("5.24e+09"), std::string::npos) << message;
    EXPECT_NE(message.find("a half-width of at most"), std::string::npos) << message;
    EXPECT_EQ(message.find("inf"), std::string::npos) << message;
    EXPECT_EQ(message.find("at most 0 "), std::string::npos) << message;
  }
  // The half-width the message advises fits at that voxel size.
  const VoxelBudgetRequest request = meshRequest(cube, 1.0 / 200, 1000);
  EXPECT_GT(estimateActiveVoxels(request), double(kDefaultMaxActiveVoxels));
}

TEST(VoxelBudget, AdvisedVoxelSizeAndHalfWidthFitAndAreTight) {
  const TriangleMesh cube = boxMesh({0, 0, 0}, {1, 1, 1});
  VoxelBudgetRequest request = meshRequest(cube, 1e-4, 3.0);
  request.maxActiveVoxels = 1'000'000;
  const double smallest = smallestVoxelSizeWithinBudget(request);
  ASSERT_TRUE(std::isfinite(smallest));
  VoxelBudgetRequest at = request;
  at.voxelSize = smallest;
  EXPECT_LE(estimateActiveVoxels(at), 1e6);
  at.voxelSize = smallest * 0.999;
  EXPECT_GT(estimateActiveVoxels(at), 1e6);
  // The refusal names that voxel size (rounded up) and the matching resolution.
  try {
    enforceVoxelBudget(request);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("a voxel size of at least"), std::string::npos) << message;
    EXPECT_NE(message.find("voxels along the longest side"), std::string::npos) << message;
  }
  // Beyond the ball of the half-width no voxel size helps.
  request.halfWidth = 100;  // 1.25 * 4/3 pi 1e6 = 5.2e6 > 1e6
  EXPECT_TRUE(std::isinf(smallestVoxelSizeWithinBudget(request)));
  EXPECT_NEAR(minimumActiveVoxels(100), 5.236e6, 1e3);
}

// The number after `prefix` in `message` (InputError text), or NaN when it is not there.
double numberAfter(const std::string& message, const std::string& prefix) {
  const std::size_t at = message.find(prefix);
  return at == std::string::npos ? std::nan("") : std::stod(message.substr(at + prefix.size()));
}

std::string refusal(const VoxelBudgetRequest& request) {
  try {
    enforceVoxelBudget(request);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(VoxelBudget, MemoryBudgetBindsBeforeTheVoxelLimitAndNamesWhatFits) {
  // field small.obj --resolution 64 --half-width 200: within the voxel limit, but not within a
  // 4 GB memory budget at a field's bytes per voxel; the ball of 200 voxels alone would not fit,
  // so the message names the half-width that does.
  const TriangleMesh cube = boxMesh({0, 0, 0}, {1, 1, 1});
  VoxelBudgetRequest request = meshRequest(cube, 1.0 / 64, 200.0);
  ASSERT_LT(estimateActiveVoxels(request), double(kDefaultMaxActiveVoxels));
  request.bytesPerVoxel = kLevelSetPeakBytesPerVoxel + kApproximantBytesPerVoxel;
  request.fixedBytes = 12 * kLevelSetBytesPerTriangle;
  request.maxMemoryBytes = 4'000'000'000;
  EXPECT_NEAR(estimateBandMemoryBytes(request),
              request.fixedBytes + request.bytesPerVoxel * estimateActiveVoxels(request), 1.0);
  ASSERT_GT(estimateBandMemoryBytes(request), double(request.maxMemoryBytes));
  std::string message = refusal(request);
  EXPECT_NE(message.find("above the memory budget of 4 GB (--max-memory)"), std::string::npos)
      << message;
  const double halfWidth = numberAfter(message, "a half-width of at most ");
  ASSERT_TRUE(halfWidth >= 1.0) << message;
  VoxelBudgetRequest narrower = request;
  narrower.halfWidth = halfWidth;
  EXPECT_LE(estimateBandMemoryBytes(narrower), double(request.maxMemoryBytes));
  narrower.halfWidth = halfWidth + 1.0;
  EXPECT_GT(estimateBandMemoryBytes(narrower), double(request.maxMemoryBytes));
  narrower.halfWidth = halfWidth;
  EXPECT_NO_THROW(enforceVoxelBudget(narrower));

  // A narrower band that a coarser voxel fits: the advised voxel size fits the memory budget.
  request.halfWidth = 20.0;
  request.maxMemoryBytes = 100'000'000;
  ASSERT_GT(estimateBandMemoryBytes(request), double(request.maxMemoryBytes));
  message = refusal(request);
  EXPECT_NE(message.find("(--max-memory)"), std::string::npos) << message;
  VoxelBudgetRequest advised = request;
  advised.voxelSize = numberAfter(message, "a voxel size of at least ");
  ASSERT_TRUE(advised.voxelSize > request.voxelSize) << message;
  EXPECT_LE(estimateBandMemoryBytes(advised), double(request.maxMemoryBytes));
  EXPECT_NO_THROW(enforceVoxelBudget(advised));
  // Without a memory figure only the voxel limit counts.
  request.bytesPerVoxel = 0;
  EXPECT_NO_THROW(enforceVoxelBudget(request));
  // meshToLevelSet() makes the same check with its options' budget.
  LevelSetOptions options;
  options.resolution = 64;
  options.halfWidth = 200;
  options.maxMemoryBytes = 4'000'000'000;
  options.extraBytesPerVoxel = kApproximantBytesPerVoxel;
  EXPECT_THROW(meshToLevelSet(cube, options), InputError);
}

}  // namespace
}  // namespace d2vdb
