// Heat-map colours (mesh/DistanceColors.h): white at 0, pure red and blue at +-scale and beyond,
// linear in between; the attributes of a mesh carry each vertex's distance and the colour scaled
// by the largest one.
#include "d2vdb/mesh/DistanceColors.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

namespace d2vdb {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

TEST(DistanceColors, WhiteAtZeroRedAndBlueAtTheScale) {
  EXPECT_EQ(distanceColor(0.0, 2.0), (Rgb{255, 255, 255}));
  EXPECT_EQ(distanceColor(2.0, 2.0), (Rgb{255, 0, 0}));
  EXPECT_EQ(distanceColor(5.0, 2.0), (Rgb{255, 0, 0}));
  EXPECT_EQ(distanceColor(-2.0, 2.0), (Rgb{0, 0, 255}));
  EXPECT_EQ(distanceColor(1.0, 2.0), (Rgb{255, 128, 128}));   // 255 * 0.5 rounded
  EXPECT_EQ(distanceColor(-0.5, 2.0), (Rgb{191, 191, 255}));  // 255 * 0.75 rounded
}

TEST(DistanceColors, AttributesCarryDistancesAndTheLargestSetsTheScale) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 4}};
  double largest = -1.0;
  const VertexAttributes attributes = distanceAttributes(
      mesh,
      [](const Eigen::Vector3d& p) {
        return p.z() > 3 ? std::numeric_limits<double>::quiet_NaN() : p.x() - p.y();
      },
      largest);
  EXPECT_EQ(attributes.scalarName, "distance");
  EXPECT_EQ(largest, 2.0);
  ASSERT_EQ(attributes.scalars.size(), 4u);
  EXPECT_EQ(attributes.scalars[1], 1.0f);
  EXPECT_EQ(attributes.scalars[2], -2.0f);
  EXPECT_EQ(attributes.scalars[3], 0.0f);  // not finite: 0
  EXPECT_EQ(attributes.colors[2], (Rgb{0, 0, 255}));
  EXPECT_EQ(attributes.colors[0], (Rgb{255, 255, 255}));
}

}  // namespace
}  // namespace d2vdb
