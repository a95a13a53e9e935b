// Shared helpers of the field tests: test meshes with known geometry, thread-count control and a
// voxel-for-voxel grid comparison.
#pragma once

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/Icosphere.h"
#include "common/WithThreads.h"
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::test {

/// Angle between the lines along a and b (0 to 90 degrees; the directions' signs do not count).
inline double lineAngleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180.0 / kPi;
}

/// Whether one of `lines` contains `text`.
inline bool containsText(const std::vector<std::string>& lines, const std::string& text) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& line) { return line.find(text) != std::string::npos; });
}

/// Icosahedron subdivided `levels` times (each level splits every triangle into four) with all
/// vertices on the sphere; triangles wound counter-clockwise seen from outside. The vertices lie
/// on the sphere, the triangles inside it (chords).
inline TriangleMesh makeIcosphere(const Eigen::Vector3d& center, double radius, int levels) {
  UnitIcosphere unit = unitIcosphere(levels);
  TriangleMesh mesh;
  for (const Eigen::Vector3d& p : unit.positions)
    mesh.positions.push_back((center + radius * p).cast<float>());
  mesh.triangles = std::move(unit.triangles);
  return mesh;
}

/// Largest distance between the sphere and the mesh's triangles (the chord error): the vertices
/// lie on the sphere, so it is radius minus the smallest centre-to-triangle distance, reached at
/// the foot of the perpendicular from the centre (inside each near-equilateral triangle).
inline double icosphereChordError(const TriangleMesh& mesh, const Eigen::Vector3d& center,
                                  double radius) {
  double smallest = radius;
  for (const TriangleMesh::Triangle& tri : mesh.triangles) {
    const Eigen::Vector3d a = mesh.positions[tri[0]].cast<double>() - center;
    const Eigen::Vector3d b = mesh.positions[tri[1]].cast<double>() - center;
    const Eigen::Vector3d c = mesh.positions[tri[2]].cast<double>() - center;
    const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
    smallest = std::min(smallest, std::abs(normal.dot(a)));
  }
  return radius - smallest;
}

/// The unit cube [0, 1]^3 as 12 triangles, counter-clockwise seen from outside.
inline TriangleMesh makeUnitCube() {
  TriangleMesh cube;
  for (int i = 0; i < 8; ++i) {
    cube.positions.emplace_back(float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1));
  }
  cube.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return cube;
}

/// Closest point to `p` on the triangle (a, b, c), by the Voronoi regions of its vertices, edges
/// and face (barycentric tests).
inline Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  }
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

/// Exact (unsigned) distance from `p` to the mesh by brute force over all triangles (skipping
/// those that provably cannot beat the best distance so far).
inline double bruteForceMeshDistance(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const TriangleMesh::Triangle& tri : mesh.triangles) {
    const Eigen::Vector3d a = mesh.positions[tri[0]].cast<double>();
    const Eigen::Vector3d b = mesh.positions[tri[1]].cast<double>();
    const Eigen::Vector3d c = mesh.positions[tri[2]].cast<double>();
    // A triangle's points lie within its longest edge of vertex a.
    const double reach = std::max({(b - a).norm(), (c - a).norm()});
    if ((p - a).norm() - reach >= best) continue;
    best = std::min(best, (p - closestPointOnTriangle(p, a, b, c)).norm());
  }
  return best;
}

/// A flat square sheet [-half, half]^2 in the plane z = 0, cells x cells quads split in two.
inline TriangleMesh makeSquareSheet(double half, int cells) {
  TriangleMesh mesh;
  for (int j = 0; j <= cells; ++j) {
    for (int i = 0; i <= cells; ++i) {
      mesh.positions.emplace_back(static_cast<float>(-half + 2.0 * half * i / cells),
                                  static_cast<float>(-half + 2.0 * half * j / cells), 0.0f);
    }
  }
  const auto vertex = [cells](int i, int j) {
    return static_cast<std::uint32_t>(j * (cells + 1) + i);
  };
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      mesh.triangles.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
      mesh.triangles.push_back({vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
    }
  }
  return mesh;
}

/// Expects the two grids to be identical voxel for voxel and bit for bit: same transform, class,
/// background, tree topology (leaves, tiles, active states) and every stored value's bits.
inline void expectBitwiseIdentical(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  EXPECT_EQ(a.transform(), b.transform());
  EXPECT_EQ(a.getGridClass(), b.getGridClass());
  EXPECT_EQ(std::memcmp(&a.background(), &b.background(), sizeof(float)), 0);
  ASSERT_TRUE(a.tree().hasSameTopology(b.tree()));
  ASSERT_EQ(a.tree().leafCount(), b.tree().leafCount());
  ASSERT_EQ(a.tree().activeVoxelCount(), b.tree().activeVoxelCount());
  std::size_t differing = 0;
  auto valueA = a.tree().cbeginValueAll();
  auto valueB = b.tree().cbeginValueAll();
  for (; valueA && valueB; ++valueA, ++valueB) {
    const float va = *valueA;
    const float vb = *valueB;
    if (valueA.getCoord() != valueB.getCoord() || valueA.isValueOn() != valueB.isValueOn() ||
        valueA.getDepth() != valueB.getDepth() || std::memcmp(&va, &vb, sizeof(float)) != 0) {
      ++differing;
    }
  }
  EXPECT_FALSE(valueA) << "first grid has more values";
  EXPECT_FALSE(valueB) << "second grid has more values";
  EXPECT_EQ(differing, 0u);
}

}  // namespace d2vdb::test
