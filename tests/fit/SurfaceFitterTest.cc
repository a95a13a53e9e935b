// Surface fitting against analytic shapes (exact targets, independent of the approximant field):
// cylinder and its offsets, the ruled hyperbolic paraboloid (exact target and point cloud) and
// hyperboloid, a torus from wrong radii (SDM against PDM), a noisy cloud (SDM II), determinism and
// bad input. Distances are measured against the analytic shapes on dense samples of the result.
#include "d2vdb/fit/SurfaceFitter.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "FitTestSupport.h"
#include "SurfaceFitTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/SurfaceTarget.h"
#include "d2vdb/fit/InitialSurface.h"
#include "d2vdb/fit/OffsetTarget.h"

namespace d2vdb {
namespace {

struct Errors {
  double max = 0.0;
  double rms = 0.0;
};

/// Max and RMS of `distance` over a samplesU x samplesV parameter grid of the surface.
Errors errorsOf(const BSplineSurface& surface,
                const std::function<double(const Eigen::Vector3d&)>& distance, int samplesU,
                int samplesV) {
  Errors errors;
  const std::vector<Eigen::Vector3d> samples = surface.sample(samplesU, samplesV);
  for (const Eigen::Vector3d& p : samples) {
    const double d = distance(p);
    errors.max = std::max(errors.max, d);
    errors.rms += d * d;
  }
  errors.rms = std::sqrt(errors.rms / static_cast<double>(samples.size()));
  return errors;
}

void print(const char* name, const SurfaceFitResult& result, const Errors& errors) {
  std::printf("%s: %d iterations (%s: %s), max %.4g, RMS %.4g\n", name, result.iterations(),
              fitStatusName(result.status), result.reason.c_str(), errors.max, errors.rms);
}

TEST(SurfaceFitter, CylinderWithTwelveControlPointsAroundReachesTheCircleFloor) {
  const test::ExactCylinderTarget target(1.0);
  const BSplineSurface initial =
      cylinderSurface(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0, 2), 1.3,
                      SurfaceLayout{3, 3, 12, 5, true, false});
  const SurfaceFitResult result = fitSurface(initial, target, {});
  const Errors errors = errorsOf(
      result.surface, [&](const Eigen::Vector3d& p) { return target.distance(p); }, 481, 9);
  print("cylinder R = 1, 12 around", result, errors);
  EXPECT_EQ(result.status, FitStatus::Converged) << result.reason;
  EXPECT_LE(errors.max, 1.2e-4);  // floor: 1.05e-4
  EXPECT_GE(errors.max, 1.0e-4);  // cannot beat the circle floor
}

TEST(SurfaceFitter, CylinderOffsetsOutwardAndInward) {
  const test::ExactCylinderTarget base(1.0);
  for (const double r : {0.25, -0.25}) {
    const OffsetTarget target(base, r);
    const BSplineSurface initial =
        cylinderSurface(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0, 2), 1.0 + 0.6 * r,
                        SurfaceLayout{3, 3, 12, 5, true, false});
    const SurfaceFitResult result = fitSurface(initial, target, {});
    const Errors errors = errorsOf(
        result.surface,
        [&](const Eigen::Vector3d& p) { return std::abs(p.head<2>().norm() - (1.0 + r)); }, 481, 9);
    print(r > 0 ? "offset +0.25" : "offset -0.25", result, errors);
    EXPECT_LE(errors.max, 1.2 * (1.0 + r) * 1.05e-4);
  }
}

BSplineSurface hyperbolicParaboloid() {
  return BSplineSurface::clamped(1, 1, 2, 2,
                                 {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1, 0),
                                  Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 1)});
}

/// Largest vertical distance |z - xy| of the surface's samples to the infinite paraboloid z = xy
/// (an upper bound of the distance to it) and the largest distance of the surface's corners to
/// the corners of the unit square (how far the sheet's extent is off the data's).
struct ParaboloidErrors {
  double shape = 0.0;
  double corners = 0.0;
};
ParaboloidErrors paraboloidErrors(const BSplineSurface& surface) {
  ParaboloidErrors errors;
  for (const Eigen::Vector3d& p : surface.sample(41, 41)) {
    errors.shape = std::max(errors.shape, std::abs(p.z() - p.x() * p.y()));
  }
  for (const double u : {0.0, 1.0}) {
    for (const double v : {0.0, 1.0}) {
      const Eigen::Vector3d corner =
          surface.evaluate(surface.domainU().at(u), surface.domainV().at(v));
      double nearest = std::numeric_limits<double>::infinity();
      for (const double x : {0.0, 1.0}) {
        for (const double y : {0.0, 1.0}) {
          nearest = std::min(nearest, (corner - Eigen::Vector3d(x, y, x * y)).norm());
        }
      }
      errors.corners = std::max(errors.corners, nearest);
    }
  }
  return errors;
}

// The cloud has 20k points; 5k keep this test short (SDM II projects every point on every
// line-search step).
TEST(SurfaceFitter, RuledHyperbolicParaboloidFromItsExactTargetAndFromACloud) {
  const SurfaceTarget target(hyperbolicParaboloid());
  const BSplineSurface initial =
      planeSheet(Eigen::Vector3d(0, 0, 0.25), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                 SurfaceLayout{1, 3, 2, 4, false, false});
  // From the target, with the automatic thin-plate weight: the distance from the sheet to the
  // target is one-sided, so any part of the paraboloid fits and, without smoothing, the sheet
  // slides over it (among exact and near-exact sub-sheets) for many iterations; the automatic
  // weight holds the parametrisation and fades with the RMS distance.
  SurfaceFitOptions options;
  options.maxIterations = 20;
  const SurfaceFitResult fromTarget = fitSurface(initial, target, options);
  const ParaboloidErrors targetErrors = paraboloidErrors(fromTarget.surface);
  std::printf("hyperbolic paraboloid, exact target: %d iterations (%s: %s), shape %.3g\n",
              fromTarget.iterations(), fitStatusName(fromTarget.status), fromTarget.reason.c_str(),
              targetErrors.shape);
  std::mt19937 engine(1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> cloud;
  for (int i = 0; i < 5000; ++i) {
    const double x = unit(engine), y = unit(engine);
    cloud.emplace_back(x, y, x * y);
  }
  // From the cloud without smoothing (the data hold the sheet on both sides).
  options.smoothness = 0.0;
  const SurfaceFitResult fromCloud = fitSurfaceToPoints(initial, cloud, options);
  const ParaboloidErrors cloudErrors = paraboloidErrors(fromCloud.surface);
  std::printf("hyperbolic paraboloid, 5k cloud: %d iterations (%s: %s), shape %.3g, corners %.3g\n",
              fromCloud.iterations(), fitStatusName(fromCloud.status), fromCloud.reason.c_str(),
              cloudErrors.shape, cloudErrors.corners);
  // An exact representation exists: the shape is exact to 1e-8. The cloud decides the sheet's
  // extent (within the spacing of its outermost points); the target does not (one-sided).
  EXPECT_LE(targetErrors.shape, 1e-8);
  EXPECT_NE(fromTarget.status, FitStatus::IterationCap) << fromTarget.reason;
  EXPECT_EQ(fromCloud.status, FitStatus::Converged) << fromCloud.reason;
  EXPECT_LE(cloudErrors.shape, 1e-8);
  EXPECT_LE(cloudErrors.corners, 0.02);
}

TEST(SurfaceFitter, RuledHyperboloidThroughBoundaryCircles) {
  const test::ExactHyperboloidTarget target(1.0);
  // A twisted cylinder of radius 1.3: the rims turned by -45 and +45 degrees, so that the rulings
  // already lean like the hyperboloid's (from an untwisted cylinder the rulings would have to turn
  // by 90 degrees, a large tangential move that the one-sided distance does not ask for: the strip
  // rather shrinks to the waist).
  const BSplineSurface cylinder =
      cylinderSurface(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0, 2), 1.3,
                      SurfaceLayout{1, 3, 2, 16, false, true});
  std::vector<Eigen::Vector3d> twisted = cylinder.controlPoints();
  for (std::size_t i = 0; i < twisted.size(); ++i) {
    const double angle = (i < 16 ? -1.0 : 1.0) * test::kTwoPi / 8.0;
    twisted[i].head<2>() = Eigen::Rotation2Dd(angle) * Eigen::Vector2d(twisted[i].head<2>());
  }
  BSplineSurface initial = cylinder;
  initial.setControlPoints(twisted);
  // No thin-plate energy: its twist term 2 |s_uv|^2 would shrink the twisted rulings toward the
  // waist, where nothing (the distance is one-sided) holds them at the rims.
  SurfaceFitOptions options;
  options.maxIterations = 15;
  options.smoothness = 0.0;
  options.stepSmoothness = 1e-3;
  const SurfaceFitResult result = fitSurface(initial, target, options);
  const Errors errors = errorsOf(
      result.surface, [&](const Eigen::Vector3d& p) { return target.distance(p); }, 41, 401);
  print("hyperboloid (1, 3), 16 per boundary", result, errors);
  EXPECT_LE(errors.max, 4.5e-5);  // construction through optimal boundary circles: 3.72e-5
  // Only the sensors beyond the rims pull them outward (the distance is one-sided), so the strip
  // ends a little short of them.
  EXPECT_NEAR(result.surface.evaluate(0.0, 0.3).z(), -1.0, 0.1);
  EXPECT_NEAR(result.surface.evaluate(1.0, 0.3).z(), 1.0, 0.1);
}

// The 16 x 16 torus from wrong radii (the main case) takes seconds: bench_fit's
// BM_SurfaceConverge rows and BENCHMARKS.md record it; here the 8 x 8 net.
TEST(SurfaceFitter, TorusFromWrongRadiiSdmAgainstPdm) {
  const test::ExactTorusTarget target(2.0, 0.5);
  const SurfaceLayout layout{3, 3, 8, 8, true, true};
  const BSplineSurface initial =
      torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.7, 0.8, layout);
  const auto distance = [&](const Eigen::Vector3d& p) { return target.distance(p); };
  // The iterations themselves, without the chord-length restart: SDM well ahead of PDM at equal
  // iteration counts. From these radii the first steps crowd the sensors' parameters around the
  // tube, which then slide back only slowly (tangential moves barely change the distances).
  SurfaceFitOptions options;
  options.maxIterations = 30;
  options.reparametrize = false;
  const SurfaceFitResult sdm = fitSurface(initial, target, options);
  const Errors sdmErrors = errorsOf(sdm.surface, distance, 161, 97);
  print("torus 8 x 8, SDM without restart", sdm, sdmErrors);
  options.method = FitMethod::PDM;
  const SurfaceFitResult pdm = fitSurface(initial, target, options);
  const Errors pdmErrors = errorsOf(pdm.surface, distance, 161, 97);
  print("torus 8 x 8, PDM without restart", pdm, pdmErrors);
  EXPECT_LE(sdmErrors.max, 2.3e-3);
  EXPECT_LE(sdmErrors.rms, 7e-4);
  EXPECT_LT(2.0 * sdmErrors.max, pdmErrors.max);
  EXPECT_LT(3.0 * sdmErrors.rms, pdmErrors.rms);
  // With the restart (the default): after 8 iterations the parameters are spread by chord length
  // and the fit continues from there. It ends below the RMS of the tensor product of the two
  // optimal circle fits (the least-squares fit trades a little maximum for RMS: the issue's
  // max <= 1.9e-3 holds on the torus field, where moves below 1/100 voxel end the sliding first;
  // BENCHMARKS.md) and well below the run without restart.
  SurfaceFitOptions restart;
  restart.maxIterations = 30;
  const SurfaceFitResult respread = fitSurface(initial, target, restart);
  const Errors respreadErrors = errorsOf(respread.surface, distance, 161, 97);
  print("torus 8 x 8, SDM with restart", respread, respreadErrors);
  const Errors circleFits =
      errorsOf(torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 2.0, 0.5, layout),
               distance, 161, 97);
  EXPECT_LT(respreadErrors.rms, circleFits.rms);
  EXPECT_LE(respreadErrors.max, 2.0e-3);
  EXPECT_LT(respreadErrors.rms, 0.9 * sdmErrors.rms);
  // The tensor product of the two optimal circle fits of the 16 x 16 net (max 9.65e-5) is a fixed
  // point of the fit.
  const BSplineSurface construction =
      torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 2.0, 0.5,
                   SurfaceLayout{3, 3, 16, 16, true, true});
  SurfaceFitOptions refine;
  refine.maxIterations = 2;
  const Errors fixedPoint =
      errorsOf(fitSurface(construction, target, refine).surface, distance, 161, 97);
  EXPECT_LE(fixedPoint.max, 1.1e-4);
  EXPECT_LE(fixedPoint.rms, 7e-5);
}

TEST(SurfaceFitter, NoisyCloudSdmTwo) {
  // z = 0.1 sin(3x) cos(2y) on [0, 2]^2 with noise sigma = 0.002 in every coordinate, 12 x 12
  // bicubic (4000 points here, to keep the test short; the 100k points are a benchmark
  // row, and the bound scales with the point count).
  const auto height = [](double x, double y) { return 0.1 * std::sin(3 * x) * std::cos(2 * y); };
  constexpr int kPoints = 4000;
  std::mt19937 engine(4);
  std::uniform_real_distribution<double> unit(0.0, 2.0);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::vector<Eigen::Vector3d> clean, noisy;
  for (int i = 0; i < kPoints; ++i) {
    const double x = unit(engine), y = unit(engine);
    clean.emplace_back(x, y, height(x, y));
    noisy.push_back(clean.back() + Eigen::Vector3d(noise(engine), noise(engine), noise(engine)));
  }
  InitialSurfaceOptions placement;
  placement.layout = SurfaceLayout{3, 3, 12, 12, false, false};
  const BSplineSurface initial = initialSurfaceAround(noisy, placement);
  const SurfaceFitResult fit = fitSurfaceToPoints(initial, noisy, {});
  // The noise-free floor: the same fit to the clean points. On clean data the geometric tolerance
  // shrinks with the RMS distance and the sheet's boundary keeps creeping, so it runs to a cap of
  // 20 iterations, where its RMS to the surface is already far below the noise term.
  SurfaceFitOptions floorOptions;
  floorOptions.maxIterations = 20;
  const SurfaceFitResult floorFit =
      fitSurfaceToPoints(initialSurfaceAround(clean, placement), clean, floorOptions);
  // RMS to the clean surface: vertical distance at the footprint of each sample of the middle
  // [0.1, 1.9]^2 (the boundary of the sheet is not part of the claim).
  const auto rmsToClean = [&](const BSplineSurface& surface) {
    double sum = 0.0;
    int count = 0;
    for (const Eigen::Vector3d& p : surface.sample(61, 61)) {
      if (p.x() < 0.1 || p.x() > 1.9 || p.y() < 0.1 || p.y() > 1.9) continue;
      sum += std::pow(p.z() - height(p.x(), p.y()), 2);
      ++count;
    }
    return std::sqrt(sum / count);
  };
  const double noisyRms = rmsToClean(fit.surface);
  const double floor = rmsToClean(floorFit.surface);
  const double expected = 0.002 * std::sqrt(3.0 * 12 * 12 / kPoints);
  std::printf(
      "noisy cloud: %d iterations (%s), RMS to clean %.4g, noise-free floor %.4g (%d iterations, "
      "%s), sigma sqrt(3mn/N) %.4g\n",
      fit.iterations(), fitStatusName(fit.status), noisyRms, floor, floorFit.iterations(),
      fitStatusName(floorFit.status), expected);
  EXPECT_EQ(fit.status, FitStatus::Converged) << fit.reason;
  EXPECT_LE(fit.iterations(), 30);
  EXPECT_LE(noisyRms, 1.15 * expected + floor);
}

TEST(SurfaceFitter, OneAndTwoThreadsGiveIdenticalSurfaces) {
  const test::ExactTorusTarget target(2.0, 0.5);
  const BSplineSurface initial = torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(),
                                              1.8, 0.6, SurfaceLayout{3, 3, 8, 8, true, true});
  SurfaceFitOptions options;
  options.maxIterations = 4;
  const SurfaceFitResult one =
      test::withThreads(1, [&] { return fitSurface(initial, target, options); });
  const SurfaceFitResult two =
      test::withThreads(2, [&] { return fitSurface(initial, target, options); });
  EXPECT_EQ(one.surface.controlPoints(), two.surface.controlPoints());
  // Through the chord-length restart (after iteration 8).
  SurfaceFitOptions restart;
  restart.maxIterations = 10;
  const BSplineSurface wrongRadii = torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(),
                                                 1.7, 0.8, SurfaceLayout{3, 3, 8, 8, true, true});
  const SurfaceFitResult restartOne =
      test::withThreads(1, [&] { return fitSurface(wrongRadii, target, restart); });
  const SurfaceFitResult restartTwo =
      test::withThreads(2, [&] { return fitSurface(wrongRadii, target, restart); });
  EXPECT_NE(restartOne.reason.find("chord length"), std::string::npos) << restartOne.reason;
  EXPECT_EQ(restartOne.surface.controlPoints(), restartTwo.surface.controlPoints());
  std::vector<Eigen::Vector3d> cloud = one.surface.sample(60, 40);
  for (Eigen::Vector3d& p : cloud) p *= 1.01;
  const SurfaceFitResult cloudOne =
      test::withThreads(1, [&] { return fitSurfaceToPoints(initial, cloud, options); });
  const SurfaceFitResult cloudTwo =
      test::withThreads(2, [&] { return fitSurfaceToPoints(initial, cloud, options); });
  EXPECT_EQ(cloudOne.surface.controlPoints(), cloudTwo.surface.controlPoints());
}

// A 24 x 24 net: 1728 unknowns, over QuadraticModel::kSimplicialUnknowns (the supernodal
// Cholesky factorises its systems). Not in the ThreadSanitizer run (its name does not match
// tools/tsan.sh's filter): instrumented, the fit takes minutes, and the factorisation it adds is
// an uninstrumented library's.
TEST(SurfaceFitter, LargeNetGivesTheSameSurfaceForEveryThreadCount) {
  const test::ExactTorusTarget target(2.0, 0.5);
  SurfaceFitOptions large;
  large.maxIterations = 3;
  large.sensorsPerSpan = 3;
  const BSplineSurface fine = torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.8,
                                           0.6, SurfaceLayout{3, 3, 24, 24, true, true});
  const SurfaceFitResult largeOne =
      test::withThreads(1, [&] { return fitSurface(fine, target, large); });
  const SurfaceFitResult largeTwo =
      test::withThreads(2, [&] { return fitSurface(fine, target, large); });
  EXPECT_EQ(largeOne.iterations(), 3);
  EXPECT_EQ(largeOne.surface.controlPoints(), largeTwo.surface.controlPoints());
}

TEST(SurfaceFitter, BadInputIsRejected) {
  const test::ExactCylinderTarget target(1.0);
  const BSplineSurface initial =
      cylinderSurface(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0, 2), 1.2,
                      SurfaceLayout{3, 3, 8, 4, true, false});
  // Outside the target's working domain.
  const BSplineSurface far = cylinderSurface(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0, 2),
                                             5.0, SurfaceLayout{3, 3, 8, 4, true, false});
  EXPECT_THROW(fitSurface(far, target, {}), InputError);
  // Fewer points than unknowns, NaN, empty.
  std::vector<Eigen::Vector3d> few(10, Eigen::Vector3d(1, 0, 0));
  EXPECT_THROW(fitSurfaceToPoints(initial, few, {}), InputError);
  std::vector<Eigen::Vector3d> cloud = initial.sample(20, 20);
  cloud[7].x() = std::nan("");
  EXPECT_THROW(fitSurfaceToPoints(initial, cloud, {}), InputError);
  EXPECT_THROW(fitSurfaceToPoints(initial, {}, {}), InputError);
  SurfaceFitOptions options;
  options.maxIterations = -1;
  EXPECT_THROW(fitSurface(initial, target, options), InputError);
}

}  // namespace
}  // namespace d2vdb
