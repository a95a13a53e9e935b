// The memory budget of the surface fitters: the sensor and ruling counts the estimates use
// against the sensors and rulings really made, and the refusal (before any allocation) naming
// the largest --sensors that fits, found by a linear scan here.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/SurfaceTarget.h"
#include "d2vdb/fit/InitialSurface.h"
#include "d2vdb/fit/RuledSurface.h"
#include "d2vdb/fit/SurfaceFitter.h"
#include "d2vdb/fit/detail/SurfaceSensorBasis.h"

namespace d2vdb {
namespace {

using Eigen::Vector3d;

BSplineSurface sheet(int countU, int countV, int degreeU = 3) {
  SurfaceLayout layout;
  layout.degreeU = degreeU;
  layout.countU = countU;
  layout.countV = countV;
  return planeSheet(Vector3d::Zero(), Vector3d::UnitX(), Vector3d::UnitY(), layout);
}

std::vector<BSplineSurface> layouts() {
  SurfaceLayout layout;
  layout.countU = 9;
  layout.countV = 7;
  layout.closedU = true;
  const BSplineSurface cylinder = cylinderSurface(Vector3d::Zero(), Vector3d::UnitZ(), 1.0, layout);
  layout.closedV = true;
  const BSplineSurface torus = torusSurface(Vector3d::Zero(), Vector3d::UnitZ(), 2.0, 0.5, layout);
  return {sheet(5, 8), sheet(12, 4, 1), cylinder, torus};
}

TEST(SurfaceFitBudget, SensorCountIsTheNumberOfSensorsPlaced) {
  for (const BSplineSurface& surface : layouts()) {
    for (const int perSpan : {1, 3, 6}) {
      EXPECT_EQ(
          surfaceSensorCount(surface, perSpan),
          static_cast<double>(detail::uniformSurfaceSensorParameters(surface, perSpan).size()))
          << surface.countU() << " x " << surface.countV() << ", " << perSpan;
    }
  }
}

TEST(SurfaceFitBudget, RulingCountIsTheNumberOfRulingsMade) {
  SurfaceLayout layout;
  layout.degreeU = 1;
  layout.countU = 4;
  layout.countV = 9;
  layout.closedV = true;
  const BSplineSurface closed = cylinderSurface(Vector3d::Zero(), Vector3d::UnitZ(), 1.0, layout);
  for (const BSplineSurface& surface : {sheet(3, 6, 1), sheet(5, 11, 1), closed}) {
    for (const int samples : {0, 1, 4}) {
      EXPECT_EQ(surfaceRulingCount(surface, samples),
                static_cast<double>(surfaceRulings(surface, samples).size()));
    }
  }
}

TEST(SurfaceFitBudget, RefusesBeforeAllocatingAndNamesTheSensorsThatFit) {
  const BSplineSurface surface = sheet(100, 100);
  ResourceBudget budget;  // the default 16 GiB
  const auto fits = [&](int s) {
    return estimateSurfaceFitMemoryBytes(surface, surfaceSensorCount(surface, s)) <=
           static_cast<double>(budget.maxMemoryBytes);
  };
  int largest = 0;
  for (int s = 1; s <= 100; ++s) {
    if (fits(s)) largest = s;
  }
  ASSERT_GT(largest, 1);
  ASSERT_LT(largest, 100);
  try {
    enforceSurfaceFitBudget(surface, surfaceSensorCount(surface, 100), 100, budget);
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("use --sensors " + std::to_string(largest) + " or fewer"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("--max-memory"), std::string::npos) << message;
  }
  EXPECT_NO_THROW(
      enforceSurfaceFitBudget(surface, surfaceSensorCount(surface, largest), largest, budget));
  // Too little memory for any sensor count: the message turns to the control points.
  budget.maxMemoryBytes = 20'000'000;
  try {
    enforceSurfaceFitBudget(surface, surfaceSensorCount(surface, 6), 6, budget);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("fewer control points (--ctrl)"), std::string::npos)
        << error.what();
  }
}

TEST(SurfaceFitBudget, BothFittersRefuseAboveTheirBudget) {
  const BSplineSurface target = sheet(4, 4);
  const SurfaceTarget exact(target);
  SurfaceFitOptions options;
  options.sensorsPerSpan = 4;
  options.budget.maxMemoryBytes = 1000;
  EXPECT_THROW(fitSurface(sheet(6, 6), exact, options), InputError);
  std::vector<Vector3d> points;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) points.emplace_back(i / 19.0, j / 19.0, 0.0);
  }
  EXPECT_THROW(fitSurfaceToPoints(sheet(6, 6), points, options), InputError);
  // Within the default budget both run.
  options.budget = ResourceBudget{};
  options.maxIterations = 2;
  EXPECT_NO_THROW(fitSurface(sheet(6, 6), exact, options));
  EXPECT_NO_THROW(fitSurfaceToPoints(sheet(6, 6), points, options));
}

}  // namespace
}  // namespace d2vdb
