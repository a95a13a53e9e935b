#include "d2vdb/spline/KnotVector.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"
#include "spline/SplineTestSupport.h"

namespace {

using d2vdb::InputError;
using d2vdb::KnotVector;

// Expects construction to throw InputError whose message contains `fragment`.
void expectRejected(int degree, const std::vector<double>& knots, const std::string& fragment) {
  try {
    KnotVector rejected(degree, knots);
    FAIL() << "expected InputError containing '" << fragment << "'";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
  }
}

TEST(KnotVector, ClampedFactoryHasRepeatedEndsAndEqualInteriorSpacing) {
  const KnotVector knots = KnotVector::clamped(3, 7, {2.0, 6.0});
  const std::vector<double> expected{2, 2, 2, 2, 3, 4, 5, 6, 6, 6, 6};
  EXPECT_EQ(knots.values(), expected);
  EXPECT_EQ(knots.degree(), 3);
  EXPECT_EQ(knots.basisFunctionCount(), 7);
  EXPECT_EQ(knots.domain().start, 2.0);
  EXPECT_EQ(knots.domain().end, 6.0);
}

TEST(KnotVector, UniformFactoryIsEquallySpacedWithTheRequestedDomain) {
  const KnotVector knots = KnotVector::uniform(2, 5, {0.0, 3.0});
  const std::vector<double> expected{-2, -1, 0, 1, 2, 3, 4, 5};
  EXPECT_EQ(knots.values(), expected);
  EXPECT_EQ(knots.domain().start, 0.0);
  EXPECT_EQ(knots.domain().end, 3.0);
}

TEST(KnotVector, PeriodicFactoryHasUniqueCountPlusTwoDegreePlusOneKnots) {
  const KnotVector knots = KnotVector::periodic(3, 4, {0.0, 4.0});
  const std::vector<double> expected{-3, -2, -1, 0, 1, 2, 3, 4, 5, 6, 7};
  EXPECT_EQ(knots.values(), expected);
  EXPECT_EQ(knots.basisFunctionCount(), 7);
  EXPECT_TRUE(knots.isUniformPeriodic());
  EXPECT_FALSE(KnotVector::clamped(3, 7).isUniformPeriodic());
  // Domain ends are exact even when the spacing is not representable.
  const KnotVector thirds = KnotVector::periodic(2, 3, {0.1, 0.7});
  EXPECT_EQ(thirds.domain().start, 0.1);
  EXPECT_EQ(thirds.domain().end, 0.7);
}

TEST(KnotVector, IsUniformPeriodicToleratesOnlyRounding) {
  std::vector<double> knots = KnotVector::periodic(2, 5).values();
  knots[4] += 1e-12;
  EXPECT_TRUE(KnotVector(2, knots).isUniformPeriodic());
  knots[4] += 1e-4;
  EXPECT_FALSE(KnotVector(2, knots).isUniformPeriodic());
}

TEST(KnotVector, FindSpanMatchesLinearSearch) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const int degree = 1 + trial % 5;
    const KnotVector knots = d2vdb::test::randomKnotVector(rng, degree, trial % 2 == 0);
    const auto domain = knots.domain();
    std::vector<double> parameters = knots.breakpoints();
    for (int i = 0; i < 20; ++i) {
      parameters.push_back(d2vdb::test::randomParameter(rng, domain.start, domain.end));
    }
    for (double t : parameters) {
      const int span = knots.findSpan(t);
      // Reference: the last index i in [p, n-1] with t_i <= t < t_{i+1}, or for t = end the
      // last non-empty span.
      int expected = -1;
      for (int i = degree; i < knots.basisFunctionCount(); ++i) {
        const bool inside = knots[i] <= t && t < knots[i + 1];
        const bool lastAtEnd = t == domain.end && knots[i] < knots[i + 1];
        if (inside || lastAtEnd) expected = i;
      }
      EXPECT_EQ(span, expected) << "t = " << t;
      EXPECT_LT(knots[span], knots[span + 1]);
    }
  }
}

TEST(KnotVector, FindSpanAtDomainEndsAndRepeatedKnots) {
  const KnotVector knots(2, {0, 0, 0, 1, 1, 2, 2, 2});
  EXPECT_EQ(knots.findSpan(0.0), 2);
  EXPECT_EQ(knots.findSpan(0.5), 2);
  EXPECT_EQ(knots.findSpan(1.0), 4);  // the repeated knot starts the next non-empty span
  EXPECT_EQ(knots.findSpan(2.0), 4);  // end of the domain: last non-empty span
}

TEST(KnotVector, FindSpanClampsRoundingAndRejectsOutsideParameters) {
  const KnotVector knots = KnotVector::clamped(3, 6, {0.0, 1.0});
  EXPECT_EQ(knots.findSpan(1.0 + 1e-16), knots.findSpan(1.0));
  EXPECT_EQ(knots.findSpan(-1e-17), knots.findSpan(0.0));
  EXPECT_THROW(knots.findSpan(1.001), InputError);
  EXPECT_THROW(knots.findSpan(-0.5), InputError);
  EXPECT_THROW(knots.findSpan(std::numeric_limits<double>::quiet_NaN()), InputError);
  try {
    knots.findSpan(3.0);
    FAIL();
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("outside the domain [0, 1]"), std::string::npos)
        << error.what();
  }
}

TEST(KnotVector, MultiplicityAndBreakpoints) {
  const KnotVector knots(3, {0, 0, 0, 0, 0.5, 0.5, 0.75, 1, 1, 1, 1});
  EXPECT_EQ(knots.multiplicity(0.0), 4);
  EXPECT_EQ(knots.multiplicity(0.5), 2);
  EXPECT_EQ(knots.multiplicity(0.75), 1);
  EXPECT_EQ(knots.multiplicity(0.6), 0);
  EXPECT_EQ(knots.breakpoints(), (std::vector<double>{0, 0.5, 0.75, 1}));
  const KnotVector unclamped = KnotVector::uniform(2, 4);
  EXPECT_EQ(unclamped.breakpoints(), (std::vector<double>{0.0, 0.5, 1.0}));
}

TEST(KnotVector, ValidationRejectsBadInputsWithClearMessages) {
  expectRejected(0, {0, 0, 1, 1}, "degree 0 is not supported");
  expectRejected(16, std::vector<double>(40, 0.0), "degree 16 is not supported");
  expectRejected(3, {0, 0, 0, 0, 1, 1, 1}, "needs at least 8");
  expectRejected(2, {0, 0, 0, 0.7, 0.5, 1, 1, 1}, "knot 4 (0.5) is less than knot 3 (0.7)");
  expectRejected(2, {0, 0, 0, std::numeric_limits<double>::quiet_NaN(), 1, 1, 1}, "knot 3 is nan");
  expectRejected(2, {0, 0, 0, 1, 1, std::numeric_limits<double>::infinity()}, "knot 5 is inf");
  expectRejected(2, {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}, "knot value 0.5 occurs 3 times");
  expectRejected(2, {0, 0, 0, 0, 1, 1, 1}, "knot value 0 occurs 4 times");
  expectRejected(1, {0, 1, 1, 1}, "is empty");
  // Allowed extremes: interior multiplicity p, end multiplicity p + 1.
  EXPECT_NO_THROW(KnotVector(2, {0, 0, 0, 0.5, 0.5, 1, 1, 1}));
  EXPECT_THROW(KnotVector::clamped(3, 3), InputError);
  EXPECT_THROW(KnotVector::periodic(3, 3), InputError);
  EXPECT_THROW(KnotVector::uniform(2, 4, {1.0, 1.0}), InputError);
}

}  // namespace
