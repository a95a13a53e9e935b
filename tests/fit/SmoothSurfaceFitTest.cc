// SDM I on a smooth surface built from a mesh: a closed 3D curve and a closed B-spline surface
// pulled onto the parametric pseudo-manifold of a torus mesh through the SmoothSurface target
// (exact projections and the surface's own curvatures, no grid).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/SmoothSurface.h"
#include "d2vdb/fit/CurveFitter.h"
#include "d2vdb/fit/InitialSurface.h"
#include "d2vdb/fit/SurfaceFitter.h"
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
    const double angle = 2.0 * kPi * i / 24;
    controls.emplace_back(4.3 * std::cos(angle), 4.3 * std::sin(angle), 0.3 * std::sin(3 * angle));
  }
  const BSplineCurve initial = BSplineCurve::closed(3, controls, 3);
  CurveFitOptions options;
  options.maxIterations = 40;
  const CurveFitResult result = fitCurve(initial, target, options);
  EXPECT_EQ(result.status, FitStatus::Converged) << result.reason;
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

TEST(SmoothSurfaceFit, TorusSurfaceFromWrongRadiiFitsAPseudoManifold) {
  // The smooth surface of a 96 x 32 torus mesh (radii 2 and 0.5) and a bicubic closed B-spline
  // torus with 16 x 16 control points started from radii 1.7 and 0.8, as the surface fitter's
  // test does against the exact torus.
  const double major = 2.0, minor = 0.5;
  const auto mesh = test::torus(major, minor, 96, 32).build();
  const LoopLimitSurface loop(mesh);
  const SmoothSurface target(std::make_shared<const PseudoManifold>(loop));
  const SurfaceLayout layout{3, 3, 16, 16, true, true};
  const BSplineSurface initial =
      torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.7, 0.8, layout);
  SurfaceFitOptions options;
  options.maxIterations = 15;
  const SurfaceFitResult result = fitSurface(initial, target, options);
  // Independent references: the exact distance to the smooth surface (its projection, checked
  // against brute force in the field tests) and to the analytic torus the mesh samples.
  const Torus torus(Eigen::Vector3d::Zero(), major, minor);
  double toSurface = 0.0, toTorus = 0.0, surfaceFromTorus = 0.0, rms = 0.0;
  const std::vector<Eigen::Vector3d> samples = result.surface.sample(97, 61);
  for (const Eigen::Vector3d& p : samples) {
    const PseudoManifold::Projection projection = target.project(p);
    toSurface = std::max(toSurface, projection.distance);
    rms += projection.distance * projection.distance;
    toTorus = std::max(toTorus, std::abs(torus.signedDistance(p)));
    surfaceFromTorus =
        std::max(surfaceFromTorus, std::abs(torus.signedDistance(projection.position)));
  }
  rms = std::sqrt(rms / static_cast<double>(samples.size()));
  std::printf(
      "B-spline torus on the pseudo-manifold of a torus: %d iterations (%s), distance to the "
      "smooth surface max %.3g RMS %.3g; to the analytic torus max %.3g (the smooth surface's "
      "own distance from it %.3g)\n",
      result.iterations(), fitStatusName(result.status), toSurface, rms, toTorus, surfaceFromTorus);
  // Not asserted converged: from these radii the sensors' parametrisation around the tube is
  // distorted by the first steps and slides back slowly (RMS 6.0e-5 after 3 iterations, 4.2e-5 at
  // convergence after 55 iterations), beyond this test's time budget; the cap stops it at
  // 15 with the accuracy asserted below.
  EXPECT_NE(result.status, FitStatus::Stalled) << result.reason;
  // On the exact torus the same fit reaches max 3e-4 and RMS 8e-5 (tests/fit/SurfaceFitterTest);
  // the smooth surface is as easy a target.
  EXPECT_LE(toSurface, 3e-4);
  EXPECT_LE(rms, 8e-5);
  EXPECT_LE(toTorus, surfaceFromTorus + 3e-4);
}

}  // namespace
}  // namespace d2vdb
