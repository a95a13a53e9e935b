#include "d2vdb/spline/BasisFunctions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "d2vdb/core/Error.h"
#include "spline/SplineTestSupport.h"

namespace {

using d2vdb::KnotVector;

TEST(BasisFunctions, PartitionOfUnityNonNegativityAndNaiveRecursion) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 300; ++trial) {
    const int degree = 1 + trial % 5;
    const KnotVector knots = d2vdb::test::randomKnotVector(rng, degree, trial % 3 != 0);
    for (int sample = 0; sample < 30; ++sample) {
      const double t = d2vdb::test::randomParameter(rng, knots.domain().start, knots.domain().end);
      const int span = knots.findSpan(t);
      const d2vdb::BasisValues values = d2vdb::basisValues(knots, span, t);
      ASSERT_EQ(values.size(), degree + 1);
      EXPECT_NEAR(values.sum(), 1.0, 1e-13);
      for (int j = 0; j <= degree; ++j) {
        EXPECT_GE(values[j], 0.0);
        EXPECT_NEAR(values[j],
                    d2vdb::test::naiveBasis(knots.values(), span - degree + j, degree, t), 1e-13);
      }
      // Every other basis function vanishes at t.
      for (int i = 0; i < knots.basisFunctionCount(); ++i) {
        if (i < span - degree || i > span) {
          EXPECT_EQ(d2vdb::test::naiveBasis(knots.values(), i, degree, t), 0.0);
        }
      }
    }
  }
}

TEST(BasisFunctions, ValuesAtDomainEndOfClampedVectorSelectLastFunction) {
  const KnotVector knots = KnotVector::clamped(3, 6, {0.0, 2.0});
  const int span = knots.findSpan(2.0);
  const d2vdb::BasisValues values = d2vdb::basisValues(knots, span, 2.0);
  for (int j = 0; j < 3; ++j) EXPECT_EQ(values[j], 0.0);
  EXPECT_DOUBLE_EQ(values[3], 1.0);
}

TEST(BasisFunctions, DerivativesMatchCentralDifferencesOfTheSpanPolynomials) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 200; ++trial) {
    const int degree = 1 + trial % 5;
    const KnotVector knots = d2vdb::test::randomKnotVector(rng, degree, trial % 2 == 0);
    for (int sample = 0; sample < 10; ++sample) {
      const double t = d2vdb::test::randomParameter(rng, knots.domain().start, knots.domain().end);
      const int span = knots.findSpan(t);
      const d2vdb::BasisDerivatives derivatives =
          d2vdb::basisDerivatives(knots, span, t, degree + 1);
      ASSERT_EQ(derivatives.rows(), degree + 2);
      ASSERT_EQ(derivatives.cols(), degree + 1);
      const d2vdb::BasisValues values = d2vdb::basisValues(knots, span, t);
      const double scale = 1.0 / (knots[span + 1] - knots[span]);
      const double h = 1e-4 / scale;
      for (int j = 0; j <= degree; ++j) EXPECT_EQ(derivatives(0, j), values[j]);
      // Order k against the central difference of order k - 1 (the span's pieces are
      // polynomials, so differencing across a knot is still exact up to O(h^2)).
      for (int k = 1; k <= degree; ++k) {
        const d2vdb::BasisDerivatives plus = d2vdb::basisDerivatives(knots, span, t + h, k - 1);
        const d2vdb::BasisDerivatives minus = d2vdb::basisDerivatives(knots, span, t - h, k - 1);
        for (int j = 0; j <= degree; ++j) {
          const double difference = (plus(k - 1, j) - minus(k - 1, j)) / (2.0 * h);
          const double tolerance = 1e-5 * std::pow(scale * 4.0 * degree, k);
          EXPECT_NEAR(derivatives(k, j), difference, tolerance) << "order " << k;
        }
      }
      // Derivatives sum to zero (partition of unity); the order above the degree vanishes.
      for (int k = 1; k <= degree; ++k) {
        EXPECT_NEAR(derivatives.row(k).sum(), 0.0, 1e-9 * std::pow(scale * 4.0 * degree, k));
      }
      for (int j = 0; j <= degree; ++j) EXPECT_EQ(derivatives(degree + 1, j), 0.0);
    }
  }
}

TEST(BasisFunctions, HighestSupportedDegreeStillFormsAPartitionOfUnity) {
  const KnotVector knots = KnotVector::clamped(d2vdb::kMaxSplineDegree, 20);
  for (double t : {0.0, 0.13, 0.5, 0.77, 1.0}) {
    const int span = knots.findSpan(t);
    const d2vdb::BasisDerivatives derivatives = d2vdb::basisDerivatives(knots, span, t, 2);
    EXPECT_NEAR(derivatives.row(0).sum(), 1.0, 1e-12);
    EXPECT_GE(derivatives.row(0).minCoeff(), 0.0);
  }
}

TEST(BasisFunctions, RejectsInvalidSpanAndOrder) {
  const KnotVector knots(2, {0, 0, 0, 0.5, 0.5, 1, 1, 1});
  EXPECT_THROW(d2vdb::basisValues(knots, 1, 0.1), d2vdb::InputError);
  EXPECT_THROW(d2vdb::basisValues(knots, 5, 0.1), d2vdb::InputError);
  EXPECT_THROW(d2vdb::basisValues(knots, 3, 0.5), d2vdb::InputError);  // empty span [0.5, 0.5)
  EXPECT_THROW(d2vdb::basisDerivatives(knots, 2, 0.1, -1), d2vdb::InputError);
  EXPECT_THROW(d2vdb::basisDerivatives(knots, 2, 0.1, d2vdb::kMaxSplineDegree + 1),
               d2vdb::InputError);
}

}  // namespace
