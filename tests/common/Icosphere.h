// The subdivided icosahedron on the unit sphere, a closed test mesh shared by the field and
// manifold tests.
#pragma once

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::test {

/// Vertices (double precision) and triangles of a closed mesh.
struct UnitIcosphere {
  std::vector<Eigen::Vector3d> positions;
  std::vector<TriangleMesh::Triangle> triangles;
};

/// Icosahedron with vertices on the unit sphere, subdivided `levels` times (each level splits
/// every triangle into four, the edge midpoints pushed to the sphere); the 12 icosahedron vertices
/// come first (degree 5), then the midpoints in the order they were made (degree 6). Triangles
/// are wound counter-clockwise seen from outside; they lie inside the sphere (chords).
inline UnitIcosphere unitIcosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  UnitIcosphere m;
  m.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Eigen::Vector3d& p : m.positions) p.normalize();
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      const auto index = static_cast<std::uint32_t>(m.positions.size() - 1);
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<TriangleMesh::Triangle> finer;
    finer.reserve(m.triangles.size() * 4);
    for (const TriangleMesh::Triangle& tri : m.triangles) {
      const std::uint32_t ab = midpoint(tri[0], tri[1]);
      const std::uint32_t bc = midpoint(tri[1], tri[2]);
      const std::uint32_t ca = midpoint(tri[2], tri[0]);
      finer.push_back({tri[0], ab, ca});
      finer.push_back({tri[1], bc, ab});
      finer.push_back({tri[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    m.triangles = std::move(finer);
  }
  // Counter-clockwise seen from outside.
  for (TriangleMesh::Triangle& tri : m.triangles) {
    const Eigen::Vector3d& a = m.positions[tri[0]];
    const Eigen::Vector3d& b = m.positions[tri[1]];
    const Eigen::Vector3d& c = m.positions[tri[2]];
    if ((b - a).cross(c - a).dot(a + b + c) < 0.0) std::swap(tri[1], tri[2]);
  }
  return m;
}

}  // namespace d2vdb::test
