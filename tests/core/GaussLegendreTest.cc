// Gauss-Legendre rules on [-1, 1] against exact integrals of monomials and the closed-form
// two-point rule.
#include <gtest/gtest.h>

#include <cmath>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/GaussLegendre.h"

namespace d2vdb {
namespace {

TEST(GaussLegendre, ExactForPolynomialsOfDegreeTwoCountMinusOne) {
  for (const int count : {1, 2, 3, 5, 8, 13, 40}) {
    const GaussLegendreRule rule = gaussLegendreRule(count);
    ASSERT_EQ(rule.nodes.size(), static_cast<std::size_t>(count));
    for (int degree = 0; degree <= 2 * count - 1; ++degree) {
      double sum = 0.0;
      for (int i = 0; i < count; ++i) {
        sum += rule.weights[static_cast<std::size_t>(i)] *
               std::pow(rule.nodes[static_cast<std::size_t>(i)], degree);
      }
      // int_-1^1 x^d dx = 2 / (d + 1) for even d, 0 for odd d.
      const double exact = degree % 2 == 0 ? 2.0 / (degree + 1) : 0.0;
      EXPECT_NEAR(sum, exact, 1e-13) << count << " points, degree " << degree;
    }
  }
}

TEST(GaussLegendre, TwoPointRuleAndLargeRules) {
  const GaussLegendreRule two = gaussLegendreRule(2);
  EXPECT_NEAR(two.nodes[0], 1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(two.nodes[1], -1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(two.weights[0], 1.0, 1e-15);
  // A large rule: nodes strictly decreasing inside (-1, 1), weights positive and summing to 2,
  // and int_-1^1 cos(x) dx = 2 sin(1).
  const GaussLegendreRule large = gaussLegendreRule(201);
  double weightSum = 0.0, cosine = 0.0;
  for (std::size_t i = 0; i < large.nodes.size(); ++i) {
    EXPECT_GT(large.weights[i], 0.0);
    EXPECT_LT(std::abs(large.nodes[i]), 1.0);
    if (i > 0) {
      EXPECT_LT(large.nodes[i], large.nodes[i - 1]);
    }
    weightSum += large.weights[i];
    cosine += large.weights[i] * std::cos(large.nodes[i]);
  }
  EXPECT_NEAR(weightSum, 2.0, 1e-12);
  EXPECT_NEAR(cosine, 2.0 * std::sin(1.0), 1e-12);
}

TEST(GaussLegendre, CountOutOfRangeIsRejected) {
  EXPECT_THROW(gaussLegendreRule(0), InputError);
  EXPECT_THROW(gaussLegendreRule(1001), InputError);
}

}  // namespace
}  // namespace d2vdb
