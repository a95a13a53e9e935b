// SDM I on a smooth surface built from a mesh: a closed 3D curve pulled onto the parametric
// pseudo-manifold of a torus mesh through the SmoothSurface target (exact projections and the
// surface's own curvatures, no grid).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "d2vdb/field/SmoothSurface.h"
#include "d2vdb/fit/CurveFitter.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "manifold/ManifoldTestSupport.h"

namespace d2vdb {
namespace {

TEST(SmoothSurfaceFit, ClosedCurveIsPulledOntoAPseudoManifold) {
  const auto mesh = test::torus(3.0, 1.0, 48, 16).build();
  const LoopLimitSurface loop(mesh);
  const SmoothSurface target(std::make_shared<const PseudoManifold>(loop));
  // A wavy loop around the torus's outer equator, 0.2 - 0.4 outside it.
  std::vector<Eigen::Vector3d> controls;
  for (int i = 0; i < 24; ++i) {
    const double angle = 2.0 * test::kPi * i / 24;
    controls.emplace_back(4.3 * std::cos(angle), 4.3 * std::sin(angle), 0.3 * std::sin(3 * angle));
  }
  const BSplineCurve initial = BSplineCurve::closed(3, controls, 3);
  CurveFitOptions options;
  options.maxIterations = 40;
  const CurveFitResult result = fitCurve(initial, target, options);
  EXPECT_NE(result.status, FitStatus::Stalled) << result.reason;
  double worst = 0.0;
  for (const Eigen::Vector3d& p : result.curve.sample(500)) {
    worst = std::max(worst, target.project(p).distance);  // exact distance to the surface
  }
  std::printf(
      "pseudo-manifold of a torus: %d iterations (%s), max distance %.3g, RMS %.3g -> %.3g\n",
      result.iterations(), fitStatusName(result.status), worst, result.history.front().rmsDistance,
      result.history.back().rmsDistance);
  EXPECT_LT(worst, 1e-4);
}

}  // namespace
}  // namespace d2vdb
