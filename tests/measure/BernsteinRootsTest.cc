// Root isolation of Bernstein polynomials: known roots, roots at the ends and at subdivision
// points, multiple roots, clusters, no roots, the zero polynomial, invalid options.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/measure/detail/BernsteinRoots.h"

namespace {

using d2vdb::BernsteinPolynomial;
using d2vdb::detail::findBernsteinRoots;

// prod_i (t - roots[i]) in Bernstein form, from linear factors with coefficients {-r, 1 - r}.
BernsteinPolynomial productOfLinearFactors(const std::vector<double>& roots) {
  BernsteinPolynomial product = BernsteinPolynomial::constant(1.0);
  for (const double root : roots) product = product * BernsteinPolynomial({-root, 1.0 - root});
  return product;
}

TEST(BernsteinRoots, FindsSimpleRootsToFullPrecision) {
  const std::vector<double> expected = {0.2, 0.5, 0.9};
  const auto found = findBernsteinRoots(productOfLinearFactors(expected));
  ASSERT_EQ(found.roots.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(found.roots[i], expected[i], 1e-14);
  EXPECT_FALSE(found.identicallyZero);
  EXPECT_FALSE(found.depthLimitReached);
}

TEST(BernsteinRoots, SeedProjectionPolynomialHasTheExactRoots) {
  // (C - p) . C' of the worked example's quadratic Bézier and p = (0, 0): 2 (2t - 1)(8t^2 - 8t +
  // 1).
  const BernsteinPolynomial f({-2.0, 14.0 / 3.0, -14.0 / 3.0, 2.0});
  const auto found = findBernsteinRoots(f);
  ASSERT_EQ(found.roots.size(), 3u);
  EXPECT_NEAR(found.roots[0], 0.5 - std::sqrt(2.0) / 4.0, 1e-15);
  EXPECT_NEAR(found.roots[1], 0.5, 1e-15);
  EXPECT_NEAR(found.roots[2], 0.5 + std::sqrt(2.0) / 4.0, 1e-15);
}

TEST(BernsteinRoots, RootsAtTheEndsAndAtSubdivisionPoints) {
  const auto ends = findBernsteinRoots(productOfLinearFactors({0.0, 1.0}));
  ASSERT_EQ(ends.roots.size(), 2u);
  EXPECT_NEAR(ends.roots[0], 0.0, 1e-13);
  EXPECT_NEAR(ends.roots[1], 1.0, 1e-13);
  // Dyadic roots fall exactly on midpoints of the subdivision; each is reported once.
  const std::vector<double> dyadic = {0.25, 0.5, 0.75};
  const auto found = findBernsteinRoots(productOfLinearFactors(dyadic));
  ASSERT_EQ(found.roots.size(), dyadic.size());
  for (std::size_t i = 0; i < dyadic.size(); ++i) EXPECT_NEAR(found.roots[i], dyadic[i], 1e-13);
}

TEST(BernsteinRoots, MultipleRootIsReportedOnce) {
  const auto doubleRoot = findBernsteinRoots(productOfLinearFactors({0.3, 0.3}));
  ASSERT_EQ(doubleRoot.roots.size(), 1u);
  EXPECT_NEAR(doubleRoot.roots[0], 0.3, 1e-7);
  const auto tripleRoot = findBernsteinRoots(productOfLinearFactors({0.6, 0.6, 0.6, 0.1}));
  ASSERT_EQ(tripleRoot.roots.size(), 2u);
  EXPECT_NEAR(tripleRoot.roots[0], 0.1, 1e-13);
  EXPECT_NEAR(tripleRoot.roots[1], 0.6, 1e-5);
}

TEST(BernsteinRoots, ManyCloseRoots) {
  std::vector<double> expected;
  for (int i = 0; i < 12; ++i) expected.push_back(0.05 + 0.08 * i);
  const auto found = findBernsteinRoots(productOfLinearFactors(expected));
  ASSERT_EQ(found.roots.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(found.roots[i], expected[i], 1e-12);
}

TEST(BernsteinRoots, NoRootsAndTheZeroPolynomial) {
  // (t - 1/2)^2 + 1/100 > 0.
  const BernsteinPolynomial positive =
      productOfLinearFactors({0.5, 0.5}) + BernsteinPolynomial::constant(0.01, 2);
  EXPECT_TRUE(findBernsteinRoots(positive).roots.empty());
  // A root just outside [0, 1] is not reported.
  EXPECT_TRUE(findBernsteinRoots(productOfLinearFactors({1.001, -0.002})).roots.empty());
  const auto zero = findBernsteinRoots(BernsteinPolynomial({0.0, 0.0, 0.0}));
  EXPECT_TRUE(zero.identicallyZero);
  EXPECT_TRUE(zero.roots.empty());
  const auto constant = findBernsteinRoots(BernsteinPolynomial::constant(3.0, 4));
  EXPECT_FALSE(constant.identicallyZero);
  EXPECT_TRUE(constant.roots.empty());
}

TEST(BernsteinRoots, DepthLimitIsReportedNotHung) {
  d2vdb::detail::RootIsolationOptions options;
  options.maxDepth = 2;
  const auto found = findBernsteinRoots(productOfLinearFactors({0.3, 0.3001, 0.7}), options);
  EXPECT_TRUE(found.depthLimitReached);
  EXPECT_FALSE(found.roots.empty());
}

TEST(BernsteinRoots, InvalidOptionsAreRejected) {
  const BernsteinPolynomial f({-1.0, 1.0});
  d2vdb::detail::RootIsolationOptions options;
  options.parameterTolerance = 0.0;
  EXPECT_THROW(findBernsteinRoots(f, options), d2vdb::InputError);
  options = {};
  options.maxDepth = 0;
  EXPECT_THROW(findBernsteinRoots(f, options), d2vdb::InputError);
}

}  // namespace
