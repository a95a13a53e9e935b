// SDM II: fitting to noisy point clouds, determinism, the attached approximant and bad input.
#include "d2vdb/fit/PointCloudFitter.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "FitTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/fit/InitialCurve.h"
#include "d2vdb/fit/detail/PointCloudProblem.h"
#include "d2vdb/fit/detail/QuadraticModel.h"

#include <utility>

namespace d2vdb {
namespace {

std::vector<Eigen::Vector3d> noisyEllipse(double sigma, int count, unsigned seed) {
  std::mt19937 engine(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  std::uniform_real_distribution<double> angle(0.0, test::kTwoPi);
  const test::ParametricCurve ellipse = test::ellipseCurve(1.0, 0.6);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    points.push_back(ellipse.point(angle(engine)) +
                     Eigen::Vector3d(noise(engine), noise(engine), 0));
  }
  return points;
}

TEST(PointCloudFitter, NoisyEllipseCloudIsFittedWithinHalfTheNoise) {
  const double size = 2.0;
  const double sigma = 0.01 * size;
  const std::vector<Eigen::Vector3d> cloud = noisyEllipse(sigma, 2000, 7);
  const BSplineCurve initial = initialCurveAround(cloud, InitialShape::Circle, 3, 12, 2, 1.3);
  CurveFitOptions options;
  options.maxIterations = 100;
  options.smoothness = 1e-8;  // a little bending energy keeps the fit from chasing the noise
  const CurveFitResult result = fitCurveToPoints(initial, cloud, options);
  // The exact second-order terms stop the footpoints sliding along the curve: it converges.
  EXPECT_EQ(result.status, FitStatus::Converged) << result.reason;
  EXPECT_LE(result.iterations(), 30);
  const test::DistanceStats clean = test::splineToCurve(result.curve, test::ellipseCurve(1.0, 0.6));
  std::printf(
      "noisy cloud SDM II: %d iterations, RMS to clean %.3g (sigma %.3g), max %.3g, data "
      "RMS %.3g\n",
      result.iterations(), clean.rms, sigma, clean.max, result.history.back().rmsDistance);
  EXPECT_LE(clean.rms, sigma / 2.0);
  // The residual RMS of the data is about the noise level.
  EXPECT_NEAR(result.history.back().rmsDistance, sigma, 0.2 * sigma);
}

TEST(PointCloudFitter, SdmNeedsFarFewerIterationsThanPdm) {
  const std::vector<Eigen::Vector3d> cloud = noisyEllipse(0.002, 1500, 11);
  const BSplineCurve initial = initialCurveAround(cloud, InitialShape::Circle, 3, 14, 2, 1.3);
  CurveFitOptions options;
  options.smoothness = 1e-8;
  options.maxIterations = 100;
  options.method = FitMethod::SDM;
  const CurveFitResult sdmLimit = fitCurveToPoints(initial, cloud, options);
  EXPECT_EQ(sdmLimit.status, FitStatus::Converged) << sdmLimit.reason;
  // Both methods run until their RMS reaches 1.05 x the RMS SDM converges to.
  options.distanceTolerance = 1.05 * sdmLimit.history.back().rmsDistance;
  options.objectiveTolerance = 0.0;
  options.stepTolerance = 0.0;
  options.maxIterations = 2000;
  const CurveFitResult sdm = fitCurveToPoints(initial, cloud, options);
  options.method = FitMethod::PDM;
  const CurveFitResult pdm = fitCurveToPoints(initial, cloud, options);
  std::printf("cloud: to RMS %.5g SDM %d iterations (%s), PDM %d iterations (%s)\n",
              options.distanceTolerance, sdm.iterations(), fitStatusName(sdm.status),
              pdm.iterations(), fitStatusName(pdm.status));
  EXPECT_EQ(sdm.status, FitStatus::Converged);
  EXPECT_LE(5 * sdm.iterations(), pdm.iterations());
}

TEST(PointCloudFitter, HelixCloudIn3D) {
  const test::ParametricCurve helix = test::helixCurve(1.0, 0.25, 1.5);
  std::vector<Eigen::Vector3d> cloud = test::samplePoints(helix, 1500);
  std::vector<Eigen::Vector3d> coarse = test::samplePoints(helix, 30);
  for (std::size_t i = 0; i < coarse.size(); ++i) coarse[i].z() += 0.05 * std::sin(1.7 * i);
  const BSplineCurve initial = fitPolylineLeastSquares(coarse, false, 3, 20, 3);
  CurveFitOptions options;
  options.maxIterations = 80;
  const CurveFitResult result = fitCurveToPoints(initial, cloud, options);
  const test::DistanceStats stats = test::splineToCurve(result.curve, helix);
  std::printf("helix cloud: %d iterations (%s), max %.3g\n", result.iterations(),
              fitStatusName(result.status), stats.max);
  EXPECT_LT(stats.max, 2e-3);
}

TEST(PointCloudFitter, AttachedApproximantMatchesTheSeedsErrorTerm) {
  // Circle of radius ~1 as a closed cubic; data point outside (convex side) and inside.
  std::vector<Eigen::Vector3d> controls;
  for (int i = 0; i < 16; ++i) {
    controls.emplace_back(std::cos(test::kTwoPi * i / 16), std::sin(test::kTwoPi * i / 16), 0.0);
  }
  const BSplineCurve circle = BSplineCurve::closed(3, controls, 2);
  const double t = circle.domain().at(0.3);
  const CurveDerivatives d = circle.derivatives(t);
  const double speed = d.first.norm();
  const Eigen::Vector3d tangent = d.first / speed;
  const Eigen::Vector3d kappaN = (d.second - d.second.dot(tangent) * tangent) / (speed * speed);
  const double rho = 1.0 / kappaN.norm();
  const Eigen::Vector3d inward = kappaN.normalized();
  const double dist = 0.3;
  const Eigen::Vector3d outside = d.point - dist * inward;
  const Approximant a = curveApproximantAt(circle, t, outside);
  EXPECT_NEAR(a.sdmWeights()[0], dist / (dist + rho), 1e-12);
  const Approximant b = curveApproximantAt(circle, t, d.point + dist * inward);
  EXPECT_EQ(b.sdmWeights()[0], 0.0);  // concave side: TDM
}

TEST(PointCloudFitter, OneAndTwoThreadsGiveIdenticalFits) {
  const std::vector<Eigen::Vector3d> cloud = noisyEllipse(0.02, 3000, 3);
  const BSplineCurve initial = initialCurveAround(cloud, InitialShape::Ellipse, 3, 12, 2, 1.2);
  CurveFitOptions options;
  options.maxIterations = 10;
  const CurveFitResult one =
      test::withThreads(1, [&] { return fitCurveToPoints(initial, cloud, options); });
  const CurveFitResult two =
      test::withThreads(2, [&] { return fitCurveToPoints(initial, cloud, options); });
  ASSERT_EQ(one.history.size(), two.history.size());
  for (std::size_t k = 0; k < one.history.size(); ++k) {
    EXPECT_EQ(one.history[k].objective, two.history[k].objective);
  }
  EXPECT_EQ(one.curve.controlPoints(), two.curve.controlPoints());
}

TEST(PointCloudFitter, BadInputIsRejected) {
  const BSplineCurve initial =
      initialCurveAround(noisyEllipse(0.01, 100, 1), InitialShape::Circle, 3, 8, 2);
  try {
    fitCurveToPoints(initial, {});
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("empty"), std::string::npos);
  }
  EXPECT_THROW(fitCurveToPoints(initial, {Eigen::Vector3d(0, 0, 1)}), InputError);  // z in 2D
  EXPECT_THROW(fitCurveToPoints(initial, {Eigen::Vector3d(NAN, 0, 0)}), InputError);
  EXPECT_THROW(initialCurveAround({}, InitialShape::Circle, 3, 8, 2), InputError);
  EXPECT_THROW(initialCurveAround(std::vector<Eigen::Vector3d>(5, Eigen::Vector3d::Ones()),
                                  InitialShape::Circle, 3, 8, 3),
               InputError);
}

}  // namespace
}  // namespace d2vdb

namespace d2vdb {
namespace {

// The exact second-order terms of SDM II: with them the model's curvature along a direction is the
// true objective's (second differences of the projected squared distances); the plain SDM term
// over-estimates it along the curve's slide, which is what made SDM II crawl.
TEST(PointCloudFitter, SecondOrderTermsGiveTheObjectivesCurvature) {
  const test::ParametricCurve loop = test::threeLobedLoop();
  const test::GeneratedCloud cloud =
      test::generateCloud(loop, 2, test::Sampling::Noisy, 600, 2.4, 4);
  CurveFitOptions options;
  const CurveFitResult fit =
      fitCurveToPoints(initialCurveAround(cloud.points, InitialShape::Ellipse, 3, 12, 2, 1.2),
                       cloud.points, options);
  ASSERT_EQ(fit.status, FitStatus::Converged) << fit.reason;
  const std::vector<Eigen::Vector3d>& points = fit.curve.controlPoints();
  const int n = fit.curve.controlPointCount();
  detail::PointCloudProblem problem(fit.curve, cloud.points, options);
  const auto objective = [&](const std::vector<Eigen::Vector3d>& net) {
    const detail::DataError error = problem.measure(net);
    return error.sum / error.count;
  };
  objective(points);
  problem.accept();
  detail::FitLinearization linearization;
  problem.linearize(points, linearization);
  ASSERT_FALSE(linearization.secondOrder.empty());
  detail::QuadraticModel model(n, 2, Eigen::SparseMatrix<double>());
  model.assemble(
      {{linearization.basis, &linearization.forms,
        1.0 / static_cast<double>(linearization.forms.size()), &linearization.secondOrder}},
      points);
  // Directions: every control point slid along the control polygon (the curve sliding along
  // itself), and a smooth normal-ish wave.
  std::vector<Eigen::Vector3d> slide(static_cast<std::size_t>(n));
  std::vector<Eigen::Vector3d> wave(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d along = points[static_cast<std::size_t>((i + 1) % n)] -
                                  points[static_cast<std::size_t>((i + n - 1) % n)];
    slide[static_cast<std::size_t>(i)] = along.normalized();
    wave[static_cast<std::size_t>(i)] = std::sin(2.0 * test::kTwoPi * i / n) *
                                        Eigen::Vector3d(-along.y(), along.x(), 0).normalized();
  }
  const double e0 = objective(points);
  for (const auto& [name, direction] :
       {std::pair<const char*, const std::vector<Eigen::Vector3d>*>{"slide", &slide},
        std::pair<const char*, const std::vector<Eigen::Vector3d>*>{"wave", &wave}}) {
    const double h = 1e-3;
    std::vector<Eigen::Vector3d> plus(points), minus(points), step(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      step[i] = h * (*direction)[i];
      plus[i] += step[i];
      minus[i] -= step[i];
    }
    const double trueCurvature = (objective(plus) + objective(minus) - 2.0 * e0) / (h * h);
    std::vector<Eigen::Vector3d> negative(step);
    for (Eigen::Vector3d& c : negative) c = -c;
    const auto modelCurvature = [&](double rankOneScale) {
      model.solveAssembled(rankOneScale, 1e-3);
      return -(model.predictedDecrease(step) + model.predictedDecrease(negative)) / (h * h);
    };
    const double exact = modelCurvature(1.0);
    const double plain = modelCurvature(0.0);
    std::printf(
        "%s: curvature of the objective %.6g, model with second-order terms %.6g, plain "
        "SDM %.6g\n",
        name, trueCurvature, exact, plain);
    EXPECT_NEAR(exact, trueCurvature, 1e-3 * std::abs(trueCurvature)) << name;
    if (direction == &slide) {
      EXPECT_GT(plain, 1.1 * trueCurvature);
    }
  }
}

}  // namespace
}  // namespace d2vdb
