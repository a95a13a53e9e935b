#include "d2vdb/support/SupportFit.h"

#include <gtest/gtest.h>

#include <Eigen/QR>

#include <chrono>
#include <cmath>

#include "SupportTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/support/detail/SupportDesign.h"

namespace d2vdb {
namespace {

double maxSurfaceError(const SupportFunction& h, const test::Ellipsoid& ellipsoid,
                       const std::vector<Eigen::Vector3d>& normals) {
  double worst = 0.0;
  const auto points = h.points(normals);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    worst = std::max(worst, (points[i] - ellipsoid.point(normals[i])).norm());
  }
  return worst;
}

TEST(SupportFit, ReproducesASphereExactly) {
  const Eigen::Vector3d center(1.0, -0.5, 2.0);
  const double radius = 0.8;
  OrientedSamples samples;
  samples.normals = test::randomUnitVectors(500, 3);
  for (const auto& n : samples.normals) samples.points.push_back(center + radius * n);
  SupportFitReport report;
  const SupportFunction h = fitSupportFunction(samples, {8, 0.0}, &report);
  const Eigen::VectorXd& c = h.coefficients();
  EXPECT_NEAR(c[0], radius * std::sqrt(4 * kPi), 1e-12);
  EXPECT_LT((h.linearPart() - center).norm(), 1e-12);
  EXPECT_LT(c.tail(c.size() - 4).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(report.maxResidual, 1e-12);
  for (const auto& n : test::randomUnitVectors(100, 4)) {
    EXPECT_LT((h.point(n) - (center + radius * n)).norm(), 1e-12);
  }
}

TEST(SupportFit, TranslatedAndOffsetSamplesChangeOnlyDegreesZeroAndOne) {
  const test::Ellipsoid ellipsoid;
  const OrientedSamples base = ellipsoid.samples(1500, 5);
  const SupportFitOptions options{10, 1e-6};
  const SupportFunction h = fitSupportFunction(base, options);
  const Eigen::Vector3d t(0.3, -1.1, 0.6);
  const double d = 0.45;
  OrientedSamples moved = base;
  for (std::size_t i = 0; i < moved.points.size(); ++i) {
    moved.points[i] += t + d * moved.normals[i];
  }
  const SupportFunction g = fitSupportFunction(moved, options);
  const Eigen::VectorXd difference = g.coefficients() - h.coefficients();
  EXPECT_NEAR(difference[0], d * std::sqrt(4 * kPi), 1e-12);
  EXPECT_LT((g.linearPart() - h.linearPart() - t).norm(), 1e-12);
  EXPECT_LT(difference.tail(difference.size() - 4).cwiseAbs().maxCoeff(), 1e-12);
}

// The normal matrix is formed from the Gram matrix of the harmonic values and ladder matrices;
// with no regularisation the solution must equal the least-squares solution of the explicit
// 3N x (L+1)^2 design matrix by Householder QR.
TEST(SupportFit, EqualsTheQrSolutionOfTheExplicitDesignMatrix) {
  const test::Ellipsoid ellipsoid{2.0, 1.5, 1.0, Eigen::Vector3d(0.2, 0.1, -0.3)};
  const OrientedSamples samples = ellipsoid.samples(400, 8);
  const int degree = 7;
  const SupportFunction h = fitSupportFunction(samples, {degree, 0.0});
  const Eigen::MatrixXd design = detail::supportDesignMatrix(samples.normals, degree);
  Eigen::VectorXd target(design.rows());
  for (std::size_t i = 0; i < samples.points.size(); ++i) {
    target.segment<3>(3 * static_cast<Eigen::Index>(i)) = samples.points[i];
  }
  const Eigen::VectorXd reference = design.householderQr().solve(target);
  EXPECT_LT((h.coefficients() - reference).cwiseAbs().maxCoeff(), 1e-11);
  // The design matrix itself reproduces x_h.
  const Eigen::VectorXd predicted = design * h.coefficients();
  for (std::size_t i = 0; i < 20; ++i) {
    EXPECT_LT((predicted.segment<3>(3 * static_cast<Eigen::Index>(i)) - h.point(samples.normals[i]))
                  .norm(),
              1e-12);
  }
}

TEST(SupportFit, EllipsoidErrorFallsGeometricallyWithTheDegree) {
  const test::Ellipsoid ellipsoid;
  const OrientedSamples samples = ellipsoid.samples(3000, 17);
  const auto normals = test::randomUnitVectors(5000, 18);
  std::vector<double> errors;
  for (const int degree : {4, 8, 12}) {
    errors.push_back(maxSurfaceError(fitSupportFunction(samples, {degree}), ellipsoid, normals));
  }
  // The error should fall about ten times per four degrees; demand at least five.
  EXPECT_LT(errors[1], errors[0] / 5.0);
  EXPECT_LT(errors[2], errors[1] / 5.0);
}

// Accuracy goals: 12k random oriented samples of the ellipsoid with semi-axes 2,
// 1.5, 1; max surface error <= 5e-5 a at L = 16 and <= 5e-7 a at L = 24, radii at +-e1 within
// 1e-4 relative at L = 24.
TEST(SupportFit, EllipsoidMeetsTheAccuracyGoalsAtDegrees16And24) {
  const test::Ellipsoid ellipsoid;
  const OrientedSamples samples = ellipsoid.samples(12000, 23);
  const auto normals = test::randomUnitVectors(6000, 24);
  SupportFitReport report16;
  const SupportFunction h16 = fitSupportFunction(samples, {16}, &report16);
  const double error16 = maxSurfaceError(h16, ellipsoid, normals);
  EXPECT_LT(error16, 5e-5 * ellipsoid.a);
  SupportFitReport report24;
  const SupportFunction h24 = fitSupportFunction(samples, {24}, &report24);
  const double error24 = maxSurfaceError(h24, ellipsoid, normals);
  EXPECT_LT(error24, 5e-7 * ellipsoid.a);
  std::printf(
      "ellipsoid fit, 12k samples: max error / a = %.3g (L = 16), %.3g (L = 24); "
      "residual rms %.3g, %.3g\n",
      error16 / ellipsoid.a, error24 / ellipsoid.a, report16.rmsResidual, report24.rmsResidual);
  const double a = ellipsoid.a, b = ellipsoid.b, c = ellipsoid.c;
  for (const double sign : {1.0, -1.0}) {
    const SupportPoint tip = h24.evaluate(sign * Eigen::Vector3d::UnitX());
    EXPECT_NEAR(tip.radius1 / (c * c / a), 1.0, 1e-4);
    EXPECT_NEAR(tip.radius2 / (b * b / a), 1.0, 1e-4);
    EXPECT_NEAR(std::abs(tip.direction1.z()), 1.0, 1e-6);  // the c axis bends most
  }
}

TEST(SupportFit, IsBitwiseIdenticalForOneAndTwoThreads) {
  const test::Ellipsoid ellipsoid;
  const OrientedSamples samples = ellipsoid.samples(5000, 31);
  const auto one = test::withThreads(1, [&] { return fitSupportFunction(samples, {12}); });
  const auto two = test::withThreads(2, [&] { return fitSupportFunction(samples, {12}); });
  EXPECT_EQ(one.coefficients(), two.coefficients());
}

TEST(SupportFit, RejectsBadSamples) {
  const test::Ellipsoid ellipsoid;
  const OrientedSamples good = ellipsoid.samples(200, 2);
  EXPECT_THROW(fitSupportFunction(good, {14}), InputError);  // 225 unknowns > 200 samples
  EXPECT_THROW(fitSupportFunction(good, {kMaxSupportDegree + 1}), InputError);
  EXPECT_THROW(fitSupportFunction(good, {4, -1.0}), InputError);
  OrientedSamples bad = good;
  bad.normals[7] = Eigen::Vector3d::Zero();
  EXPECT_THROW(fitSupportFunction(bad, {4}), InputError);
  bad = good;
  bad.normals[9].x() = std::nan("");
  EXPECT_THROW(fitSupportFunction(bad, {4}), InputError);
  bad = good;
  bad.points[3].z() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(fitSupportFunction(bad, {4}), InputError);
  bad = good;
  bad.points.pop_back();
  EXPECT_THROW(fitSupportFunction(bad, {4}), InputError);
  EXPECT_THROW(fitSupportFunction(OrientedSamples{}, {0}), InputError);
  // Normals off unit length are normalised and counted.
  OrientedSamples scaled = good;
  for (int i = 0; i < 5; ++i) scaled.normals[static_cast<std::size_t>(i)] *= 3.0;
  SupportFitReport report;
  const SupportFunction h = fitSupportFunction(scaled, {4}, &report);
  EXPECT_EQ(report.renormalizedNormals, 5u);
  EXPECT_NEAR(report.largestNormalDeviation, 2.0, 1e-12);
  EXPECT_LT((h.coefficients() - fitSupportFunction(good, {4}).coefficients()).cwiseAbs().maxCoeff(),
            1e-13);
}

}  // namespace
}  // namespace d2vdb
