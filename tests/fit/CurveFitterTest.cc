// SDM I: B-spline curves fitted to curve targets (ellipse, offset, helix), the convergence order
// of SDM against PDM, determinism and input errors.
#include "d2vdb/fit/CurveFitter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "FitTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/fit/InitialCurve.h"
#include "d2vdb/fit/OffsetTarget.h"

namespace d2vdb {
namespace {

using test::ellipseCurve;
using test::ParametricCurve;

constexpr double kA = 1.0;
constexpr double kB = 0.6;
constexpr double kEllipseSize = 2.0 * kA;  // largest extent of the ellipse

Polyline ellipsePolyline(int count) {
  Polyline polyline;
  polyline.points = test::samplePoints(ellipseCurve(kA, kB), count);
  polyline.closed = true;
  polyline.dimension = 2;
  return polyline;
}

// A circle of radius 1.3 around the ellipse: a closed cubic with 12 control points.
BSplineCurve initialCircle() {
  return initialCurveAround(ellipsePolyline(64).points, InitialShape::Circle, 3, 12, 2, 1.3);
}

double maxControlPointDistance(const BSplineCurve& a, const BSplineCurve& b) {
  double worst = 0.0;
  for (int i = 0; i < a.controlPointCount(); ++i) {
    worst = std::max(worst, (a.controlPoints()[static_cast<std::size_t>(i)] -
                             b.controlPoints()[static_cast<std::size_t>(i)])
                                .norm());
  }
  return worst;
}

TEST(CurveFitter, ClosedCubicWithTwelveControlPointsFitsAnEllipsePolyline) {
  const CurveTarget target(ellipsePolyline(4000));
  CurveFitOptions options;
  options.method = FitMethod::SDM;
  options.maxIterations = 50;
  options.stepTolerance = 1e-9;
  const CurveFitResult result = fitCurve(initialCircle(), target, options);
  EXPECT_EQ(result.status, FitStatus::Converged) << result.reason;
  EXPECT_LE(result.iterations(), 30);
  EXPECT_EQ(result.curve.controlPointCount(), 12);
  EXPECT_TRUE(result.curve.isClosed());
  // Both one-sided distances against the analytic ellipse (independent of the target).
  const test::DistanceStats toEllipse = test::splineToCurve(result.curve, ellipseCurve(kA, kB));
  const double fromEllipse =
      test::pointsToSpline(test::samplePoints(ellipseCurve(kA, kB), 400), result.curve);
  EXPECT_LT(toEllipse.max, 1e-3 * kEllipseSize);
  EXPECT_LT(fromEllipse, 1e-3 * kEllipseSize);
  // The reported history agrees with the reference at the sensors within the polyline's error.
  EXPECT_LT(result.history.back().maxDistance, 1e-3 * kEllipseSize);
  EXPECT_LT(result.history.back().rmsDistance, result.history.front().rmsDistance * 1e-2);
  std::printf("ellipse SDM: %d iterations, max distance %.3g (%.3g of size), reverse %.3g\n",
              result.iterations(), toEllipse.max, toEllipse.max / kEllipseSize, fromEllipse);
}

/// The seven-lobed flower r = 1 + 0.15 cos(7 t), squeezed to 0.7 in y: a wavy closed curve whose
/// bending energy is about 20 times a circle's of the same size.
ParametricCurve flowerCurve() {
  const auto point = [](double t) {
    const double r = 1.0 + 0.15 * std::cos(7.0 * t);
    return Eigen::Vector3d(r * std::cos(t), 0.7 * r * std::sin(t), 0.0);
  };
  const auto first = [](double t) {
    const double r = 1.0 + 0.15 * std::cos(7.0 * t), dr = -1.05 * std::sin(7.0 * t);
    return Eigen::Vector3d(dr * std::cos(t) - r * std::sin(t),
                           0.7 * (dr * std::sin(t) + r * std::cos(t)), 0.0);
  };
  const auto second = [](double t) {
    const double r = 1.0 + 0.15 * std::cos(7.0 * t), dr = -1.05 * std::sin(7.0 * t),
                 ddr = -7.35 * std::cos(7.0 * t);
    return Eigen::Vector3d((ddr - r) * std::cos(t) - 2.0 * dr * std::sin(t),
                           0.7 * ((ddr - r) * std::sin(t) + 2.0 * dr * std::cos(t)), 0.0);
  };
  return {point, first, second, 0.0, test::kTwoPi, true};
}

TEST(CurveFitter, DefaultOptionsDoNotFlattenAWavyClosedCurve) {
  // The automatic bending weight must not pull a wavy target's lobes in: a fixed 1e-8 left the
  // fit 0.015 (0.75 % of the size) off this flower; the automatic weight follows the fit's
  // resolution down.
  Polyline polyline;
  polyline.points = test::samplePoints(flowerCurve(), 20000);
  polyline.closed = true;
  polyline.dimension = 2;
  const CurveTarget target(polyline);
  std::vector<Eigen::Vector3d> start;
  for (const Eigen::Vector3d& p : test::samplePoints(flowerCurve(), 400)) start.push_back(1.03 * p);
  const BSplineCurve initial = fitPolylineLeastSquares(start, true, 3, 100, 2);
  const CurveFitResult result = fitCurve(initial, target, CurveFitOptions{});
  EXPECT_EQ(result.status, FitStatus::Converged) << result.reason;
  const double size = 2.0;
  const test::DistanceStats toFlower = test::splineToCurve(result.curve, flowerCurve(), 2000);
  const double fromFlower =
      test::pointsToSpline(test::samplePoints(flowerCurve(), 700), result.curve, 8000);
  std::printf("flower, default options: %d iterations, max distance %.3g, reverse %.3g\n",
              result.iterations(), toFlower.max, fromFlower);
  EXPECT_LT(toFlower.max, 1e-4 * size);
  EXPECT_LT(fromFlower, 1e-4 * size);
}

TEST(CurveFitter, SdmConvergesSuperlinearlyAndPdmLinearly) {
  // An exact target (a fine closed cubic through the ellipse; a polyline's approximants resolve
  // nothing below its vertex spacing, where the fit would stop), so that the rate can be
  // followed down to rounding.
  const CurveTarget target(fitPolylineLeastSquares(ellipsePolyline(2000).points, true, 3, 400, 2),
                           0.5);
  CurveFitOptions options;
  options.keepIterates = true;
  options.stepTolerance = 1e-10;  // the limit to 1e-10 of the size: rounding sets the floor
  options.moveTolerance = 0.0;    // run on to the step tolerance: the rate is what is measured
  options.objectiveTolerance = 0.0;
  options.maxIterations = 60;
  options.method = FitMethod::SDM;
  // A fixed bending weight gives the control points a unique limit (the automatic weight changes
  // with the RMS distance, and with it the pull on their tangential freedom).
  options.smoothness = 1e-8;
  const CurveFitResult reference = fitCurve(initialCircle(), target, options);
  ASSERT_EQ(reference.status, FitStatus::Converged) << reference.reason;

  const auto errors = [&](const CurveFitResult& result) {
    std::vector<double> e;
    for (const BSplineCurve& iterate : result.iterates) {
      e.push_back(maxControlPointDistance(iterate, reference.curve));
    }
    return e;
  };
  // SDM: e_{k+1} / e_k falls toward 0 (super-linear) while e is well above rounding.
  const std::vector<double> sdm = errors(reference);
  double lastSdmRatio = 1.0;
  std::string sdmRatios;
  for (std::size_t k = 0; k + 1 < sdm.size(); ++k) {
    if (sdm[k] < 1e-9 || sdm[k + 1] < 1e-11) break;
    lastSdmRatio = sdm[k + 1] / sdm[k];
    sdmRatios += std::to_string(lastSdmRatio) + " ";
  }
  std::printf("SDM ratios: %s\n", sdmRatios.c_str());
  EXPECT_LT(lastSdmRatio, 0.1);

  options.method = FitMethod::PDM;
  options.maxIterations = 400;
  options.stepTolerance = 0.0;
  options.objectiveTolerance = 0.0;
  const CurveFitResult pdm = fitCurve(initialCircle(), target, options);
  const std::vector<double> pdmErrors = errors(pdm);
  // PDM: the ratio settles at a constant bounded away from 0 (linear convergence).
  ASSERT_GT(pdmErrors.size(), 60u);
  double minRatio = 1.0;
  for (std::size_t k = 20; k + 1 < 60; ++k) {
    minRatio = std::min(minRatio, pdmErrors[k + 1] / pdmErrors[k]);
  }
  std::printf("PDM ratio over iterations 20..60 >= %.4f, e_20 = %.3g, e_60 = %.3g\n", minRatio,
              pdmErrors[20], pdmErrors[60]);
  EXPECT_GT(minRatio, 0.5);

  // Iterations until the control points are within 1e-3 of the size of the limit: SDM needs at
  // most a fifth of PDM's (PDM's count is at least its run length when it never gets there).
  const auto firstWithin = [&](const std::vector<double>& e) {
    for (std::size_t k = 0; k < e.size(); ++k) {
      if (e[k] < 1e-3 * kEllipseSize) return static_cast<int>(k);
    }
    return static_cast<int>(e.size());
  };
  const int sdmIterations = firstWithin(sdm);
  const int pdmIterations = firstWithin(pdmErrors);
  std::printf("iterations to within 1e-3 size of the limit: SDM %d, PDM %d%s\n", sdmIterations,
              pdmIterations, pdmIterations == static_cast<int>(pdmErrors.size()) ? "+" : "");
  EXPECT_LE(5 * sdmIterations, pdmIterations);
}

TEST(CurveFitter, TdmAndTdmPlusPdmAlsoFitTheEllipse) {
  const CurveTarget target(ellipsePolyline(4000));
  for (const FitMethod method : {FitMethod::TDM, FitMethod::TDMPlusPDM}) {
    CurveFitOptions options;
    options.method = method;
    options.maxIterations = 1000;
    options.stepTolerance = 1e-8;
    const CurveFitResult result = fitCurve(initialCircle(), target, options);
    const test::DistanceStats stats = test::splineToCurve(result.curve, ellipseCurve(kA, kB));
    std::printf("%s: %d iterations, %s, max distance %.3g\n", fitMethodName(method),
                result.iterations(), fitStatusName(result.status), stats.max);
    EXPECT_EQ(result.status, FitStatus::Converged)
        << fitMethodName(method) << ": " << result.reason;
    EXPECT_LT(stats.max, 1e-3 * kEllipseSize) << fitMethodName(method);
  }
}

TEST(CurveFitter, OffsetOfAClosedSplineMatchesExactOffsetPoints) {
  // A convex closed cubic as the progenitor; its offset at r = 0.15 outward.
  std::vector<Eigen::Vector3d> controls;
  for (int i = 0; i < 8; ++i) {
    const double angle = test::kTwoPi * i / 8;
    const double radius = 1.0 + 0.12 * std::cos(2.0 * angle);
    controls.emplace_back(radius * std::cos(angle), 0.7 * radius * std::sin(angle), 0.0);
  }
  const BSplineCurve base = BSplineCurve::closed(3, controls, 2);
  const double r = 0.15;
  const CurveTarget baseTarget(base, 1.0);
  const OffsetTarget target(baseTarget, r);

  // Exact offset points: footpoint + r * outward normal at dense parameters (2D left normal of a
  // counter-clockwise curve points inward, so the outward one is the right normal).
  std::vector<Eigen::Vector3d> exact;
  Eigen::AlignedBox3d box;
  for (int i = 0; i < 400; ++i) {
    const double t = base.domain().at(i / 400.0);
    const CurveDerivatives d = base.derivatives(t);
    const Eigen::Vector3d tangent = d.first.normalized();
    const Eigen::Vector3d outward(tangent.y(), -tangent.x(), 0.0);
    exact.push_back(d.point + r * outward);
    box.extend(exact.back());
  }
  const double size = box.sizes().maxCoeff();

  const BSplineCurve initial = initialCurveAround(exact, InitialShape::Ellipse, 3, 20, 2, 1.15);
  CurveFitOptions options;
  options.maxIterations = 60;
  const CurveFitResult result = fitCurve(initial, target, options);
  EXPECT_EQ(result.status, FitStatus::Converged) << result.reason;
  // Fitted curve -> exact offset: distance to the base curve minus r (independent projection).
  const ParameterInterval domain = base.domain();
  const ParametricCurve baseCurve{[&](double t) { return base.evaluate(t); },
                                  [&](double t) { return base.derivatives(t).first; },
                                  [&](double t) { return base.derivatives(t).second; },
                                  domain.start,
                                  domain.end,
                                  true};
  double worst = 0.0;
  for (const Eigen::Vector3d& p : result.curve.sample(800)) {
    worst = std::max(worst, std::abs(test::referenceDistance(baseCurve, p) - r));
  }
  const double reverse = test::pointsToSpline(exact, result.curve);
  std::printf("offset: %d iterations, max |d - r| %.3g, exact points to fit %.3g (size %.3g)\n",
              result.iterations(), worst, reverse, size);
  EXPECT_LT(worst, 1e-3 * size);
  EXPECT_LT(reverse, 1e-3 * size);
}

TEST(CurveFitter, HelixFittedToAHelixPolyline) {
  const ParametricCurve helix = test::helixCurve(1.0, 0.25, 2.0);
  Polyline polyline;
  polyline.points = test::samplePoints(helix, 3000);
  polyline.dimension = 3;
  const CurveTarget target(polyline);
  const double size = 2.0;  // the largest extent (the helix is 2 wide, 3.14 high)
  // Initial: a least-squares curve through a perturbed, coarse copy of the helix.
  std::vector<Eigen::Vector3d> perturbed = test::samplePoints(helix, 60);
  for (std::size_t i = 0; i < perturbed.size(); ++i) {
    perturbed[i] += Eigen::Vector3d(0.05 * std::sin(3.0 * i), 0.05 * std::cos(5.0 * i), 0.04);
  }
  const BSplineCurve initial = fitPolylineLeastSquares(perturbed, false, 3, 24, 3);
  CurveFitOptions options;
  options.maxIterations = 60;
  const CurveFitResult result = fitCurve(initial, target, options);
  EXPECT_EQ(result.status, FitStatus::Converged) << result.reason;
  const test::DistanceStats stats = test::splineToCurve(result.curve, helix);
  std::printf("helix: %d iterations (%s), max distance %.3g, rms %.3g\n", result.iterations(),
              fitStatusName(result.status), stats.max, stats.rms);
  EXPECT_LT(stats.max, 1e-3 * size);
  // The fit covers the helix: every interior helix point is near it.
  std::vector<Eigen::Vector3d> interior;
  for (int i = 1; i < 40; ++i) interior.push_back(helix.point(helix.end * i / 40.0));
  EXPECT_LT(test::pointsToSpline(interior, result.curve), 1e-3 * size);
}

TEST(CurveFitter, OneAndTwoThreadsGiveIdenticalFits) {
  const CurveTarget target(ellipsePolyline(4000));
  for (const FitMethod method : {FitMethod::SDM, FitMethod::TDM}) {
    CurveFitOptions options;
    options.method = method;
    options.maxIterations = 15;
    const CurveFitResult one =
        test::withThreads(1, [&] { return fitCurve(initialCircle(), target, options); });
    const CurveFitResult two =
        test::withThreads(2, [&] { return fitCurve(initialCircle(), target, options); });
    ASSERT_EQ(one.history.size(), two.history.size());
    for (std::size_t k = 0; k < one.history.size(); ++k) {
      EXPECT_EQ(one.history[k].objective, two.history[k].objective);
      EXPECT_EQ(one.history[k].maxDistance, two.history[k].maxDistance);
    }
    for (int i = 0; i < one.curve.controlPointCount(); ++i) {
      EXPECT_EQ(one.curve.controlPoints()[static_cast<std::size_t>(i)],
                two.curve.controlPoints()[static_cast<std::size_t>(i)]);
    }
  }
}

TEST(CurveFitter, BadInputIsRejectedWithAClearMessage) {
  const CurveTarget target(ellipsePolyline(400), 0.1);
  // All control points equal.
  const BSplineCurve collapsed =
      BSplineCurve::closed(3, std::vector<Eigen::Vector3d>(8, Eigen::Vector3d(0.2, 0.1, 0.0)), 2);
  try {
    fitCurve(collapsed, target);
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("control points coincide"), std::string::npos);
  }
  // A target whose domain does not cover the initial curve.
  std::vector<Eigen::Vector3d> big;
  for (int i = 0; i < 8; ++i) {
    big.emplace_back(10.0 * std::cos(test::kTwoPi * i / 8), 10.0 * std::sin(test::kTwoPi * i / 8),
                     0.0);
  }
  try {
    fitCurve(BSplineCurve::closed(3, big, 2), target);
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("does not cover the initial curve"), std::string::npos)
        << error.what();
  }
  // Invalid knots (decreasing) cannot even form the curve to fit.
  EXPECT_THROW(KnotVector(3, {0, 0, 0, 0, 0.7, 0.5, 1, 1, 1, 1}), InputError);
  // Invalid options.
  CurveFitOptions options;
  options.sensorsPerSpan = 0;
  EXPECT_THROW(fitCurve(initialCircle(), target, options), InputError);
  options = {};
  options.smoothness = std::nan("");
  EXPECT_THROW(fitCurve(initialCircle(), target, options), InputError);
  // Offsets need a curve target and a positive distance.
  EXPECT_THROW(OffsetTarget(target, -0.1), InputError);
  EXPECT_THROW(parseFitMethod("newton"), InputError);
}

}  // namespace
}  // namespace d2vdb
