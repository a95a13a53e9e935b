// The dilation of seed voxels into a seed band's candidates, against brute-force enumeration.
#include "d2vdb/field/detail/SeedDilation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {
namespace {

/// Every integer offset within `extent` of the origin in every coordinate.
template <typename F>
void forEachOffset(int extent, F&& f) {
  for (int x = -extent; x <= extent; ++x) {
    for (int y = -extent; y <= extent; ++y) {
      for (int z = -extent; z <= extent; ++z) f(std::array<int, 3>{x, y, z});
    }
  }
}

TEST(SeedDilation, CoversEveryVoxelCenterWithinTheRadiusOfAPointInTheSeedVoxel) {
  for (double radius = 0.3; radius <= 12.0; radius += 0.0625) {
    const SeedDilation dilation = seedDilation(radius);
    const int extent = static_cast<int>(std::ceil(radius)) + 2;
    forEachOffset(extent, [&](const std::array<int, 3>& w) {
      if (withinRadiusOfVoxel(w, radius)) {
        ASSERT_TRUE(dilation.contains(w))
            << "radius " << radius << " offset " << w[0] << " " << w[1] << " " << w[2];
      }
    });
  }
}

TEST(SeedDilation, WithinRadiusOfVoxelIsTheDistanceToTheVoxelCube) {
  // A point p in the cube [-1/2, 1/2]^3 sampled finely: the smallest |w - p| over the samples
  // approaches the distance from w to the cube from above.
  for (const std::array<int, 3> w : {std::array<int, 3>{4, 1, 1},
                                     {3, 3, 2},
                                     {3, 3, 3},
                                     {4, 2, 2},
                                     {0, 0, 0},
                                     {2, 0, 0},
                                     {-3, 2, -1}}) {
    double nearest = 1e9;
    const int samples = 40;
    for (int i = 0; i <= samples; ++i) {
      for (int j = 0; j <= samples; ++j) {
        for (int k = 0; k <= samples; ++k) {
          const double p[3] = {-0.5 + static_cast<double>(i) / samples,
                               -0.5 + static_cast<double>(j) / samples,
                               -0.5 + static_cast<double>(k) / samples};
          double squared = 0.0;
          for (int c = 0; c < 3; ++c) squared += (w[c] - p[c]) * (w[c] - p[c]);
          nearest = std::min(nearest, std::sqrt(squared));
        }
      }
    }
    // Within a radius just above the sampled distance, not within one just below it (the
    // nearest point of the cube, a corner, edge or face centre, is a sample).
    EXPECT_TRUE(withinRadiusOfVoxel(w, nearest + 1e-9));
    EXPECT_FALSE(withinRadiusOfVoxel(w, std::max(nearest - 1e-9, 0.0)));
  }
}

TEST(SeedDilation, OffsetCountIsTheNumberOfOffsetsItContains) {
  for (int c = 0; c <= 6; ++c) {
    for (int d = 0; d <= 6; ++d) {
      const SeedDilation dilation{c, d};
      std::int64_t contained = 0;
      forEachOffset(c + d + 1, [&](const std::array<int, 3>& w) {
        if (dilation.contains(w)) ++contained;
      });
      EXPECT_EQ(dilation.offsetCount(), contained) << c << " " << d;
    }
  }
}

TEST(SeedDilation, IsTheSmallestCoveringDilation) {
  for (double radius = 0.3; radius <= 8.0; radius += 0.125) {
    const SeedDilation chosen = seedDilation(radius);
    const std::int64_t chosenCount = chosen.offsetCount();
    // No dilation with as many steps as the plain cube (or fewer) covers with fewer offsets.
    const int cube = std::max(1, static_cast<int>(std::ceil(radius - 0.5)));
    for (int c = 0; c <= cube; ++c) {
      for (int d = 0; c + d <= cube; ++d) {
        const SeedDilation other{c, d};
        bool covers = true;
        forEachOffset(cube + 1, [&](const std::array<int, 3>& w) {
          if (withinRadiusOfVoxel(w, radius) && !other.contains(w)) covers = false;
        });
        if (covers) {
          EXPECT_GE(other.offsetCount(), chosenCount) << radius << " " << c << " " << d;
        }
      }
    }
  }
}

TEST(SeedDilation, KnownCases) {
  // The old candidates of a band of half-width 3 from seeds within 1.5 voxels of the target:
  // four 26-neighbour steps, 729 offsets; the rounded cube needs 637.
  const SeedDilation reach15 = seedDilation(4.5);
  EXPECT_EQ(reach15.cubeSteps, 3);
  EXPECT_EQ(reach15.diamondSteps, 1);
  EXPECT_EQ(reach15.offsetCount(), 637);
  // Seeds within 0.89 voxel (the smooth-surface field): two steps of each kind, 485 offsets.
  const SeedDilation reach089 = seedDilation(3.0 + 0.893);
  EXPECT_EQ(reach089.cubeSteps, 2);
  EXPECT_EQ(reach089.diamondSteps, 2);
  EXPECT_EQ(reach089.offsetCount(), 485);
  // Offsets counted by hand: one 26-neighbour step is the 3^3 cube, one 6-neighbour step the 7
  // voxels of the cross.
  EXPECT_EQ((SeedDilation{1, 0}.offsetCount()), 27);
  EXPECT_EQ((SeedDilation{0, 1}.offsetCount()), 7);
  EXPECT_EQ((SeedDilation{0, 2}.offsetCount()), 25);
}

TEST(SeedDilation, RefusesRadiiOutOfRange) {
  EXPECT_THROW(seedDilation(0.0), InputError);
  EXPECT_THROW(seedDilation(-1.0), InputError);
  EXPECT_THROW(seedDilation(std::nan("")), InputError);
  EXPECT_THROW(seedDilation(201.0), InputError);
}

}  // namespace
}  // namespace d2vdb::detail
