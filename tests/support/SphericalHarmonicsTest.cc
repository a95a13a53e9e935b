#include "d2vdb/support/SphericalHarmonics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "SupportTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/support/SphereQuadrature.h"

namespace d2vdb {
namespace {

// The solid harmonic polynomial sum_j c_j r^l Y_j(p / r) at any point p != 0.
double solidPolynomial(const Eigen::VectorXd& c, int degree, const Eigen::Vector3d& p) {
  const double r = p.norm();
  const Eigen::VectorXd y = evaluateHarmonics(degree, p / r);
  double sum = 0.0;
  for (int l = 0; l <= degree; ++l) {
    for (int m = -l; m <= l; ++m)
      sum += c[harmonicIndex(l, m)] * std::pow(r, l) * y[harmonicIndex(l, m)];
  }
  return sum;
}

TEST(SphericalHarmonics, MatchTheClosedFormsOfLowDegree) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.7).normalized();
  const Eigen::VectorXd y = evaluateHarmonics(2, n);
  const double x = n.x(), yy = n.y(), z = n.z();
  EXPECT_NEAR(y[harmonicIndex(0, 0)], 1.0 / std::sqrt(4 * kPi), 1e-15);
  const double s1 = std::sqrt(3.0 / (4 * kPi));
  EXPECT_NEAR(y[harmonicIndex(1, -1)], s1 * yy, 1e-15);
  EXPECT_NEAR(y[harmonicIndex(1, 0)], s1 * z, 1e-15);
  EXPECT_NEAR(y[harmonicIndex(1, 1)], s1 * x, 1e-15);
  EXPECT_NEAR(y[harmonicIndex(2, 0)], std::sqrt(5.0 / (16 * kPi)) * (3 * z * z - 1), 1e-15);
  EXPECT_NEAR(y[harmonicIndex(2, 1)], std::sqrt(15.0 / (4 * kPi)) * x * z, 1e-15);
  EXPECT_NEAR(y[harmonicIndex(2, -1)], std::sqrt(15.0 / (4 * kPi)) * yy * z, 1e-15);
  EXPECT_NEAR(y[harmonicIndex(2, 2)], std::sqrt(15.0 / (16 * kPi)) * (x * x - yy * yy), 1e-15);
  EXPECT_NEAR(y[harmonicIndex(2, -2)], std::sqrt(15.0 / (4 * kPi)) * x * yy, 1e-15);
}

TEST(SphericalHarmonics, AreOrthonormalUpToDegree24) {
  const int degree = 24;
  const SphereQuadrature rule = sphereQuadrature(2 * degree);
  const int count = harmonicCount(degree);
  Eigen::MatrixXd values(static_cast<Eigen::Index>(rule.nodes.size()), count);
  Eigen::VectorXd weights(values.rows());
  for (std::size_t q = 0; q < rule.nodes.size(); ++q) {
    values.row(static_cast<Eigen::Index>(q)) = evaluateHarmonics(degree, rule.nodes[q]).transpose();
    weights[static_cast<Eigen::Index>(q)] = rule.weights[q];
  }
  const Eigen::MatrixXd gram = values.transpose() * weights.asDiagonal() * values;
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(count, count)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(SphericalHarmonics, LadderDerivativesMatchFiniteDifferences) {
  const int degree = 9;
  std::mt19937 engine(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd c(harmonicCount(degree));
  for (Eigen::Index j = 0; j < c.size(); ++j) c[j] = uniform(engine);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.4, -0.7, 0.5), Eigen::Vector3d(0, 0, 1.2),
                                   Eigen::Vector3d(-0.9, 0.1, -0.3)}) {
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::VectorXd d = harmonicPartialDerivative(c, degree, axis);
      const double h = 1e-5;
      const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(axis);
      // Fourth-order central difference.
      const double numeric =
          (-solidPolynomial(c, degree, p + 2 * step) + 8 * solidPolynomial(c, degree, p + step) -
           8 * solidPolynomial(c, degree, p - step) + solidPolynomial(c, degree, p - 2 * step)) /
          (12 * h);
      const double exact = solidPolynomial(d, degree - 1, p);
      EXPECT_NEAR(exact, numeric, 1e-7 * (1.0 + std::abs(exact))) << "axis " << axis;
    }
  }
}

TEST(SphericalHarmonics, SolidHarmonicsAreHarmonicAndDerivativesCommute) {
  const int degree = 20;
  std::mt19937 engine(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd c(harmonicCount(degree));
  for (Eigen::Index j = 0; j < c.size(); ++j) c[j] = uniform(engine);
  Eigen::VectorXd laplacian = Eigen::VectorXd::Zero(harmonicCount(degree - 2));
  for (int axis = 0; axis < 3; ++axis) {
    laplacian +=
        harmonicPartialDerivative(harmonicPartialDerivative(c, degree, axis), degree - 1, axis);
  }
  const double scale =
      harmonicPartialDerivative(harmonicPartialDerivative(c, degree, 2), degree - 1, 2)
          .cwiseAbs()
          .maxCoeff();
  EXPECT_LT(laplacian.cwiseAbs().maxCoeff(), 1e-13 * scale);
  const Eigen::VectorXd xy =
      harmonicPartialDerivative(harmonicPartialDerivative(c, degree, 0), degree - 1, 1);
  const Eigen::VectorXd yx =
      harmonicPartialDerivative(harmonicPartialDerivative(c, degree, 1), degree - 1, 0);
  EXPECT_LT((xy - yx).cwiseAbs().maxCoeff(), 1e-13 * scale);
}

TEST(SphericalHarmonics, RejectBadDegreesAndSizes) {
  EXPECT_THROW(evaluateHarmonics(-1, Eigen::Vector3d::UnitZ()), InputError);
  EXPECT_THROW(evaluateHarmonics(kMaxSupportDegree + 1, Eigen::Vector3d::UnitZ()), InputError);
  EXPECT_THROW(harmonicPartialDerivative(Eigen::VectorXd::Zero(5), 1, 0), InputError);
  EXPECT_THROW(harmonicPartialDerivative(Eigen::VectorXd::Zero(4), 1, 3), InputError);
}

TEST(SphereQuadrature, IntegratesPolynomialsExactly) {
  const SphereQuadrature rule = sphereQuadrature(12);
  double area = 0.0, x4 = 0.0, x2y2z8 = 0.0;
  for (std::size_t q = 0; q < rule.nodes.size(); ++q) {
    const Eigen::Vector3d& n = rule.nodes[q];
    area += rule.weights[q];
    x4 += rule.weights[q] * std::pow(n.x(), 4);
    x2y2z8 += rule.weights[q] * n.x() * n.x() * n.y() * n.y() * std::pow(n.z(), 8);
  }
  EXPECT_NEAR(area, 4 * kPi, 1e-13);
  EXPECT_NEAR(x4, 4 * kPi / 5, 1e-13);
  // Integral of x^2 y^2 z^8 over S^2 = 2 Gamma(3/2)^2 Gamma(9/2) / Gamma(15/2).
  const double exact =
      2 * std::tgamma(1.5) * std::tgamma(1.5) * std::tgamma(4.5) / std::tgamma(7.5);
  EXPECT_NEAR(x2y2z8, exact, 1e-15);
}

}  // namespace
}  // namespace d2vdb
