// Helpers of the approximant-field tests: band voxel centres, random points and a bit-for-bit
// comparison of two fields' answers.
#pragma once

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <Eigen/Geometry>

#include <random>
#include <vector>

#include "d2vdb/field/ApproximantField.h"

namespace d2vdb::test {

/// Every active voxel centre of the field's band (world).
inline std::vector<Eigen::Vector3d> bandCenters(const ApproximantField& field) {
  std::vector<Eigen::Vector3d> centers;
  const auto& grid = *field.distanceGrid();
  for (auto voxel = grid.cbeginValueOn(); voxel; ++voxel) {
    const openvdb::Vec3d w = grid.indexToWorld(voxel.getCoord());
    centers.emplace_back(w.x(), w.y(), w.z());
  }
  return centers;
}

/// `count` points uniformly distributed in `box`, from a generator seeded with `seed`.
inline std::vector<Eigen::Vector3d> randomPoints(const Eigen::AlignedBox3d& box, int count,
                                                 unsigned seed = 17) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    points.push_back(
        box.min() +
        (box.sizes().array() * Eigen::Array3d(unit(random), unit(random), unit(random))).matrix());
  }
  return points;
}

/// Every approximant at the band's voxel centres and at `extra` points, compared field by field.
inline void expectSameAnswers(const ApproximantField& a, const ApproximantField& b,
                              const std::vector<Eigen::Vector3d>& extra) {
  auto points = bandCenters(a);
  points.insert(points.end(), extra.begin(), extra.end());
  const auto answersA = a.approximantsAt(points);
  const auto answersB = b.approximantsAt(points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Approximant &x = answersA[i], &y = answersB[i];
    ASSERT_TRUE(x.flags == y.flags && x.distance == y.distance && x.footpoint == y.footpoint &&
                x.normal == y.normal && x.tangent == y.tangent && x.k1 == y.k1 && x.k2 == y.k2 &&
                x.principalNormal == y.principalNormal)
        << "different answers at point " << i << ": flags " << x.flags << "/" << y.flags << " d "
        << x.distance << "/" << y.distance << " foot " << x.footpoint.transpose() << " / "
        << y.footpoint.transpose() << " n " << x.normal.transpose() << " / " << y.normal.transpose()
        << " t " << x.tangent.transpose() << " / " << y.tangent.transpose() << " k " << x.k1 << ","
        << x.k2 << " / " << y.k1 << "," << y.k2;
  }
}

}  // namespace d2vdb::test
