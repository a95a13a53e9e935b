// Curvature attributes (mesh/CurvatureColors.h): nearest-rank percentiles on hand-checked lists,
// the colours of a sphere (all convex), a saddle (flat mean) and a mixed set, and refusals.
#include "d2vdb/mesh/CurvatureColors.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

TEST(CurvatureColors, NearestRankQuantiles) {
  const std::vector<double> values{5, 1, 4, 2, 3};
  EXPECT_EQ(nearestRankQuantile(values, 0.0), 1);   // rank 1
  EXPECT_EQ(nearestRankQuantile(values, 0.2), 1);   // ceil(1.0) = rank 1
  EXPECT_EQ(nearestRankQuantile(values, 0.21), 2);  // ceil(1.05) = rank 2
  EXPECT_EQ(nearestRankQuantile(values, 0.5), 3);   // the median
  EXPECT_EQ(nearestRankQuantile(values, 0.99), 5);
  EXPECT_EQ(nearestRankQuantile(values, 1.0), 5);
  EXPECT_EQ(nearestRankQuantile(values, 7.0), 5);  // clamped
  EXPECT_EQ(nearestRankQuantile({}, 0.5), 0);
}

TEST(CurvatureColors, ASphereIsConvexEverywhere) {
  // Radius 2: k1 = k2 = H = 1/2 at every vertex, so the scale is 1/2 and every vertex is red.
  const std::vector<double> k(10, 0.5);
  const CurvatureAttributes sphere = curvatureAttributes(k, k);
  EXPECT_EQ(sphere.attributes.scalarName, "k1");
  ASSERT_EQ(sphere.attributes.scalars.size(), 10u);
  ASSERT_EQ(sphere.attributes.moreScalars.size(), 1u);
  EXPECT_EQ(sphere.attributes.moreScalars[0].first, "k2");
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_EQ(sphere.attributes.scalars[i], 0.5f);
    EXPECT_EQ(sphere.attributes.moreScalars[0].second[i], 0.5f);
    EXPECT_EQ(sphere.attributes.colors[i], (Rgb{255, 0, 0}));
  }
  EXPECT_EQ(sphere.summary.colorScale, 0.5);
  EXPECT_EQ(sphere.summary.meanRange, (std::array<double, 2>{0.5, 0.5}));
}

TEST(CurvatureColors, MixedCurvaturesScaleByTheNinetyNinthPercentileOfTheMean) {
  // H = 0 (saddle), 1, -0.5, 2 (the largest |H|: the scale at 4 values), -2.
  const std::vector<double> k1{1, 1, 0, 3, -1};
  const std::vector<double> k2{-1, 1, -1, 1, -3};
  const CurvatureAttributes mixed = curvatureAttributes(k1, k2);
  const CurvatureSummary& summary = mixed.summary;
  EXPECT_EQ(summary.colorScale, 2.0);
  EXPECT_EQ(summary.k1Range, (std::array<double, 2>{-1, 3}));
  EXPECT_EQ(summary.k2Range, (std::array<double, 2>{-3, 1}));
  EXPECT_EQ(summary.meanRange, (std::array<double, 2>{-2, 2}));
  EXPECT_EQ(summary.meanPercentiles, (std::array<double, 3>{-2, 0, 2}));
  const std::vector<Rgb> expected{
      {255, 255, 255},  // flat mean: white
      {255, 128, 128},  // half the scale, convex: 255 * 0.5 rounded
      {191, 191, 255},  // a quarter of the scale, concave: 255 * 0.75 rounded
      {255, 0, 0},
      {0, 0, 255}};
  EXPECT_EQ(mixed.attributes.colors, expected);
}

TEST(CurvatureColors, RefusesMismatchedOrNonFiniteCurvatures) {
  EXPECT_THROW(curvatureAttributes({1, 2}, {1}), InputError);
  EXPECT_THROW(curvatureAttributes({1, std::numeric_limits<double>::quiet_NaN()}, {1, 1}),
               InputError);
  const CurvatureAttributes none = curvatureAttributes({}, {});
  EXPECT_TRUE(none.attributes.colors.empty());
  EXPECT_EQ(none.summary.colorScale, 0.0);
}

}  // namespace
}  // namespace d2vdb
