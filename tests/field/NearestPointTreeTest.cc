// NearestPointTree against brute force: random clouds, a surface-like shell queried from far off
// it (the coarse levels' use), exact ties, degenerate sets, hints, thread counts and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "FieldTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/detail/NearestPointTree.h"

namespace d2vdb::detail {
namespace {

/// The brute-force answer: smallest float squared distance (computed as the tree documents),
/// ties to the lowest index.
NearestPointTree::Nearest bruteForce(const std::vector<Eigen::Vector3f>& points,
                                     const Eigen::Vector3f& query) {
  NearestPointTree::Nearest best{0, std::numeric_limits<float>::infinity()};
  for (std::size_t i = 0; i < points.size(); ++i) {
    const float dx = points[i].x() - query.x();
    const float dy = points[i].y() - query.y();
    const float dz = points[i].z() - query.z();
    const float squared = dx * dx + dy * dy + dz * dz;
    if (squared < best.squaredDistance) best = {static_cast<std::uint32_t>(i), squared};
  }
  return best;
}

/// Checks `queries` against brute force, each with a hint drawn at random (the answer must not
/// depend on it); returns how many were checked.
int expectExact(const NearestPointTree& tree, const std::vector<Eigen::Vector3f>& points,
                const std::vector<Eigen::Vector3f>& queries, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::uint32_t> anyIndex(
      0, static_cast<std::uint32_t>(points.size()) + 5);  // out of range counts as 0
  int checked = 0;
  for (const Eigen::Vector3f& query : queries) {
    const NearestPointTree::Nearest expected = bruteForce(points, query);
    const NearestPointTree::Nearest found = tree.nearest(query, anyIndex(random));
    EXPECT_EQ(found.index, expected.index) << "query " << query.transpose();
    EXPECT_EQ(found.squaredDistance, expected.squaredDistance) << "query " << query.transpose();
    ++checked;
  }
  return checked;
}

std::vector<Eigen::Vector3f> uniformPoints(int count, float extent, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> coordinate(-extent, extent);
  std::vector<Eigen::Vector3f> points(static_cast<std::size_t>(count));
  for (Eigen::Vector3f& p : points)
    p = {coordinate(random), coordinate(random), coordinate(random)};
  return points;
}

TEST(NearestPointTree, RandomCloudMatchesBruteForce) {
  const auto points = uniformPoints(5000, 10.0f, 1);
  const NearestPointTree tree(points);
  EXPECT_EQ(tree.size(), points.size());
  // Queries inside the cloud and well outside it.
  auto queries = uniformPoints(1500, 12.0f, 2);
  const auto far = uniformPoints(500, 60.0f, 3);
  queries.insert(queries.end(), far.begin(), far.end());
  EXPECT_EQ(expectExact(tree, points, queries, 4), 2000);
}

TEST(NearestPointTree, ShellQueriedFromOffTheSurfaceMatchesBruteForce) {
  // Lattice points within sqrt(3)/2 of a sphere of radius 30, projected onto it (like the field's
  // samples), queried at lattice points 0 to 20 units off the sphere, inside and outside, in the
  // coherent order the coarse levels use (each query hinted with the previous answer).
  std::vector<Eigen::Vector3f> points;
  for (int x = -32; x <= 32; ++x) {
    for (int y = -32; y <= 32; ++y) {
      for (int z = -32; z <= 32; ++z) {
        const double r = std::sqrt(double(x) * x + double(y) * y + double(z) * z);
        if (std::abs(r - 30.0) <= 0.5 * std::sqrt(3.0)) {
          points.push_back((Eigen::Vector3d(x, y, z) * (30.0 / r)).cast<float>());
        }
      }
    }
  }
  ASSERT_GT(points.size(), 15000u);
  const NearestPointTree tree(points);
  int checked = 0;
  std::uint32_t hint = 0;
  for (int x = -50; x <= 50; x += 3) {
    for (int y = -50; y <= 50; y += 3) {
      for (int z = -50; z <= 50; z += 3) {
        const double r = std::sqrt(double(x) * x + double(y) * y + double(z) * z);
        if (std::abs(r - 30.0) > 20.0 || (x + y + z) % 4 != 0) continue;
        const Eigen::Vector3f query(static_cast<float>(x), static_cast<float>(y),
                                    static_cast<float>(z));
        const NearestPointTree::Nearest expected = bruteForce(points, query);
        const NearestPointTree::Nearest found = tree.nearest(query, hint);
        ASSERT_EQ(found.index, expected.index) << query.transpose();
        ASSERT_EQ(found.squaredDistance, expected.squaredDistance) << query.transpose();
        hint = found.index;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 3000);
}

TEST(NearestPointTree, TiesGoToTheLowestIndex) {
  // Every point four times (indices i, i + n, i + 2n, i + 3n) and queries on the points, between
  // points and equidistant from several: the answer is always the lowest index at the distance.
  const auto base = uniformPoints(400, 5.0f, 5);
  std::vector<Eigen::Vector3f> points;
  for (int copy = 0; copy < 4; ++copy) points.insert(points.end(), base.begin(), base.end());
  const NearestPointTree tree(points);
  std::vector<Eigen::Vector3f> queries(base.begin(), base.begin() + 100);
  for (int i = 0; i + 1 < 100; ++i) queries.push_back(0.5f * (base[i] + base[i + 1]));
  const auto extra = uniformPoints(300, 6.0f, 6);
  queries.insert(queries.end(), extra.begin(), extra.end());
  expectExact(tree, points, queries, 7);
  for (int i = 0; i < 100; ++i) {
    EXPECT_LT(tree.nearest(base[i], static_cast<std::uint32_t>(i + 3 * 400)).index, 400u);
  }
}

TEST(NearestPointTree, DegenerateSets) {
  // One point; fewer points than a leaf holds; all on a plane; all on a line; all equal.
  const std::vector<Eigen::Vector3f> single{{1.0f, 2.0f, 3.0f}};
  const auto queries = uniformPoints(200, 8.0f, 8);
  expectExact(NearestPointTree(single), single, queries, 9);
  const auto few = uniformPoints(5, 3.0f, 10);
  expectExact(NearestPointTree(few), few, queries, 11);
  std::vector<Eigen::Vector3f> plane = uniformPoints(3000, 4.0f, 12);
  for (Eigen::Vector3f& p : plane) p.z() = 0.25f;
  expectExact(NearestPointTree(plane), plane, queries, 13);
  std::vector<Eigen::Vector3f> line = uniformPoints(3000, 4.0f, 14);
  for (Eigen::Vector3f& p : line) p.y() = p.z() = -1.0f;
  expectExact(NearestPointTree(line), line, queries, 15);
  const std::vector<Eigen::Vector3f> same(1000, Eigen::Vector3f(0.5f, 0.5f, 0.5f));
  const NearestPointTree tree(same);
  EXPECT_EQ(tree.nearest({3.0f, 0.0f, 1.0f}, 700).index, 0u);
}

TEST(NearestPointTree, SameAnswersForAnyThreadCount) {
  // Built with one and with two threads (the build splits in parallel above 16384 points).
  const auto points = uniformPoints(60000, 20.0f, 16);
  const auto queries = uniformPoints(3000, 30.0f, 17);
  const auto answers = [&](int threads) {
    return test::withThreads(threads, [&] {
      const NearestPointTree tree(points);
      std::vector<std::uint32_t> result;
      for (const Eigen::Vector3f& q : queries) result.push_back(tree.nearest(q, 0).index);
      return result;
    });
  };
  EXPECT_EQ(answers(1), answers(2));
}

TEST(NearestPointTree, RejectsEmptyAndNonFiniteInput) {
  EXPECT_THROW(NearestPointTree(std::vector<Eigen::Vector3f>{}), InputError);
  EXPECT_THROW(NearestPointTree({{0.0f, 0.0f, 0.0f}, {std::nanf(""), 1.0f, 1.0f}}), InputError);
  EXPECT_THROW(NearestPointTree({{0.0f, std::numeric_limits<float>::infinity(), 0.0f}}),
               InputError);
}

}  // namespace
}  // namespace d2vdb::detail
