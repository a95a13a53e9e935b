#include "d2vdb/spline/Bernstein.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "d2vdb/core/Error.h"
#include "spline/SplineTestSupport.h"

namespace {

using d2vdb::BernsteinPolynomial;

// Independent reference: sum_i c_i C(n,i) t^i (1-t)^(n-i) with the test's own binomials.
double explicitSum(const std::vector<double>& c, double t) {
  const int n = static_cast<int>(c.size()) - 1;
  double value = 0.0;
  for (int i = 0; i <= n; ++i) {
    value += c[static_cast<std::size_t>(i)] * d2vdb::test::binomial(n, i) * std::pow(t, i) *
             std::pow(1.0 - t, n - i);
  }
  return value;
}

std::vector<double> randomCoefficients(std::mt19937& rng, int degree) {
  std::uniform_real_distribution<double> coefficient(-3.0, 3.0);
  std::vector<double> c;
  for (int i = 0; i <= degree; ++i) c.push_back(coefficient(rng));
  return c;
}

TEST(Bernstein, BasisValuesMatchTheClosedFormAndSumToOne) {
  for (int degree = 0; degree <= d2vdb::kMaxBernsteinDegree; degree += 3) {
    for (double t : {0.0, 0.1, 0.37, 0.5, 0.93, 1.0}) {
      const d2vdb::BernsteinBasisValues values = d2vdb::bernsteinBasisValues(degree, t);
      ASSERT_EQ(values.size(), degree + 1);
      EXPECT_NEAR(values.sum(), 1.0, 1e-13);
      for (int i = 0; i <= degree; ++i) {
        const double expected =
            d2vdb::test::binomial(degree, i) * std::pow(t, i) * std::pow(1.0 - t, degree - i);
        EXPECT_NEAR(values[i], expected, 1e-13);
        EXPECT_NEAR(d2vdb::bernsteinBasis(degree, i, t), expected, 1e-13);
      }
    }
  }
  EXPECT_THROW(d2vdb::bernsteinBasis(3, 4, 0.5), d2vdb::InputError);
  EXPECT_THROW(d2vdb::bernsteinBasisValues(d2vdb::kMaxBernsteinDegree + 1, 0.5), d2vdb::InputError);
}

TEST(Bernstein, EvaluationMatchesExplicitSum) {
  std::mt19937 rng(3);
  for (int degree = 0; degree <= 12; ++degree) {
    const std::vector<double> c = randomCoefficients(rng, degree);
    const BernsteinPolynomial f(c);
    EXPECT_EQ(f.degree(), degree);
    for (int k = 0; k <= 10; ++k) {
      const double t = k / 10.0;
      EXPECT_NEAR(f.evaluate(t), explicitSum(c, t), 1e-12);
    }
  }
}

TEST(Bernstein, SubdivisionHalvesReproduceThePolynomial) {
  std::mt19937 rng(4);
  for (int degree = 1; degree <= 9; ++degree) {
    const BernsteinPolynomial f(randomCoefficients(rng, degree));
    const double split = d2vdb::test::randomParameter(rng, 0.05, 0.95);
    const auto [left, right] = f.subdivide(split);
    ASSERT_EQ(left.degree(), degree);
    ASSERT_EQ(right.degree(), degree);
    EXPECT_NEAR(left.coefficient(degree), f.evaluate(split), 1e-13);
    EXPECT_NEAR(right.coefficient(0), f.evaluate(split), 1e-13);
    for (int k = 0; k <= 8; ++k) {
      const double s = k / 8.0;
      EXPECT_NEAR(left.evaluate(s), f.evaluate(split * s), 1e-12);
      EXPECT_NEAR(right.evaluate(s), f.evaluate(split + s * (1.0 - split)), 1e-12);
    }
    const BernsteinPolynomial middle = f.restricted(0.2, 0.7);
    for (int k = 0; k <= 8; ++k) {
      const double s = k / 8.0;
      EXPECT_NEAR(middle.evaluate(s), f.evaluate(0.2 + 0.5 * s), 1e-12);
    }
  }
}

TEST(Bernstein, CoefficientBoundsEncloseTheValues) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    const BernsteinPolynomial f(randomCoefficients(rng, 1 + trial % 8));
    for (int k = 0; k <= 50; ++k) {
      const double value = f.evaluate(k / 50.0);
      EXPECT_LE(f.minCoefficient(), value + 1e-14);
      EXPECT_GE(f.maxCoefficient(), value - 1e-14);
    }
  }
  // Subdivision tightens the bounds towards the true range (here [0, 1/4] for t(1-t)).
  BernsteinPolynomial f{0.0, 0.5, 0.0};
  EXPECT_DOUBLE_EQ(f.maxCoefficient(), 0.5);
  const auto halves = f.subdivide(0.5);
  EXPECT_DOUBLE_EQ(halves.first.maxCoefficient(), 0.25);
}

TEST(Bernstein, DerivativeMatchesCentralDifference) {
  std::mt19937 rng(6);
  for (int degree = 0; degree <= 8; ++degree) {
    const BernsteinPolynomial f(randomCoefficients(rng, degree));
    const BernsteinPolynomial df = f.derivative();
    EXPECT_EQ(df.degree(), std::max(degree - 1, 0));
    const double h = 1e-5;
    for (int k = 0; k <= 10; ++k) {
      const double t = k / 10.0;
      EXPECT_NEAR(df.evaluate(t), (f.evaluate(t + h) - f.evaluate(t - h)) / (2 * h), 1e-6);
    }
  }
}

TEST(Bernstein, DegreeElevationLeavesThePolynomialUnchanged) {
  std::mt19937 rng(7);
  for (int degree = 0; degree <= 6; ++degree) {
    const BernsteinPolynomial f(randomCoefficients(rng, degree));
    const BernsteinPolynomial g = f.elevated(4);
    EXPECT_EQ(g.degree(), degree + 4);
    for (int k = 0; k <= 10; ++k) EXPECT_NEAR(g.evaluate(k / 10.0), f.evaluate(k / 10.0), 1e-13);
    EXPECT_EQ(g.coefficient(0), f.coefficient(0));
    EXPECT_EQ(g.coefficient(degree + 4), f.coefficient(degree));
  }
  EXPECT_THROW(BernsteinPolynomial::constant(1.0, 30).elevated(2), d2vdb::InputError);
}

TEST(Bernstein, ProductSumAndDifferenceMatchPointwiseArithmetic) {
  std::mt19937 rng(8);
  for (int trial = 0; trial < 30; ++trial) {
    const BernsteinPolynomial f(randomCoefficients(rng, trial % 7));
    const BernsteinPolynomial g(randomCoefficients(rng, (trial * 3) % 9));
    const BernsteinPolynomial product = f * g;
    const BernsteinPolynomial sum = f + g;
    const BernsteinPolynomial difference = f - g;
    const BernsteinPolynomial scaled = 2.5 * f;
    EXPECT_EQ(product.degree(), f.degree() + g.degree());
    for (int k = 0; k <= 12; ++k) {
      const double t = k / 12.0;
      EXPECT_NEAR(product.evaluate(t), f.evaluate(t) * g.evaluate(t), 1e-12);
      EXPECT_NEAR(sum.evaluate(t), f.evaluate(t) + g.evaluate(t), 1e-12);
      EXPECT_NEAR(difference.evaluate(t), f.evaluate(t) - g.evaluate(t), 1e-12);
      EXPECT_NEAR(scaled.evaluate(t), 2.5 * f.evaluate(t), 1e-12);
    }
  }
  EXPECT_THROW(BernsteinPolynomial::constant(1.0, 20) * BernsteinPolynomial::constant(1.0, 12),
               d2vdb::InputError);
}

// engine/README.md's worked example: for the quadratic Bézier (-1,0),(0,2),(1,0) and p = (0,0), (C
// - p) . C' is the cubic 2 (2t - 1)(8t^2 - 8t + 1). Its Bernstein coefficients come from the power
// form: 32 t^3 - 48 t^2 + 20 t - 2.
TEST(Bernstein, ProjectionConditionOfTheDesignExampleAsScalarProducts) {
  const BernsteinPolynomial x{-1.0, 0.0, 1.0};
  const BernsteinPolynomial y{0.0, 2.0, 0.0};
  const BernsteinPolynomial condition = x * x.derivative() + y * y.derivative();
  ASSERT_EQ(condition.degree(), 3);
  EXPECT_NEAR(condition.coefficient(0), -2.0, 1e-14);
  EXPECT_NEAR(condition.coefficient(1), 14.0 / 3.0, 1e-14);
  EXPECT_NEAR(condition.coefficient(2), -14.0 / 3.0, 1e-14);
  EXPECT_NEAR(condition.coefficient(3), 2.0, 1e-14);
  for (double root : {0.5 - std::sqrt(2.0) / 4.0, 0.5, 0.5 + std::sqrt(2.0) / 4.0}) {
    EXPECT_NEAR(condition.evaluate(root), 0.0, 1e-14);
  }
  for (int k = 0; k <= 10; ++k) {
    const double t = k / 10.0;
    EXPECT_NEAR(condition.evaluate(t), 32 * t * t * t - 48 * t * t + 20 * t - 2, 1e-13);
  }
}

TEST(Bernstein, RejectsInvalidCoefficients) {
  EXPECT_THROW(BernsteinPolynomial(std::vector<double>{}), d2vdb::InputError);
  EXPECT_THROW(BernsteinPolynomial(std::vector<double>(33, 1.0)), d2vdb::InputError);
  EXPECT_THROW(BernsteinPolynomial({1.0, std::nan("")}), d2vdb::InputError);
  EXPECT_THROW(BernsteinPolynomial({1.0, 2.0}).restricted(0.5, 0.5), d2vdb::InputError);
}

}  // namespace
