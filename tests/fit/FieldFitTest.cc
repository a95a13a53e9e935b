// SDM I on a surface level set: a closed 3D curve pulled onto a sphere through the approximant
// field (ApproximantField::fromLevelSet of an exact primitive level set).
#include <gtest/gtest.h>

#include <cmath>

#include "FitTestSupport.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/fit/CurveFitter.h"

namespace d2vdb {
namespace {

TEST(FieldFit, ClosedSpaceCurveIsPulledOntoASphereLevelSet) {
  const double radius = 1.0;
  PrimitiveLevelSetOptions levelSet;
  levelSet.voxelSize = 0.02;
  const ApproximantField field = ApproximantField::fromLevelSet(
      primitiveLevelSet(Sphere(Eigen::Vector3d::Zero(), radius), levelSet));
  // A wavy loop around the sphere, 0.1 - 0.3 away from it.
  std::vector<Eigen::Vector3d> controls;
  for (int i = 0; i < 16; ++i) {
    const double angle = test::kTwoPi * i / 16;
    controls.emplace_back(1.2 * std::cos(angle), 1.2 * std::sin(angle), 0.35 * std::sin(2 * angle));
  }
  const BSplineCurve initial = BSplineCurve::closed(3, controls, 3);
  CurveFitOptions options;
  options.maxIterations = 40;
  const CurveFitResult result = fitCurve(initial, field, options);
  EXPECT_EQ(result.status, FitStatus::Converged) << result.reason;
  double worst = 0.0;
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : result.curve.sample(1000)) {
    worst = std::max(worst, std::abs(p.norm() - radius));  // exact distance to the sphere
    box.extend(p);
  }
  std::printf("sphere: %d iterations (%s), max |d| %.3g, initial RMS %.3g, final RMS %.3g\n",
              result.iterations(), fitStatusName(result.status), worst,
              result.history.front().rmsDistance, result.history.back().rmsDistance);
  EXPECT_LT(worst, 1e-3 * 2.0 * radius);
  EXPECT_GT(box.sizes().head<2>().minCoeff(), 1.5);  // still a loop around the sphere
}

}  // namespace
}  // namespace d2vdb
