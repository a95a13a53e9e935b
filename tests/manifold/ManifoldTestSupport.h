// Shared helpers of the manifold tests: closed test meshes (Platonic solids, spheres, a torus, a
// mesh with vertex degrees 3 to 9), thread-count control, and an independent Loop subdivision
// written plainly with an edge map (the reference of the limit-surface tests).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "common/Icosphere.h"
#include "common/WithThreads.h"
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/manifold/HalfEdgeMesh.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::test {

/// Positions and triangles of a closed mesh in double precision.
struct DoubleMesh {
  std::vector<Eigen::Vector3d> positions;
  std::vector<TriangleMesh::Triangle> triangles;

  /// Turns every triangle counter-clockwise seen from outside a convex, star-shaped mesh around
  /// the origin.
  void orientOutward() {
    for (TriangleMesh::Triangle& t : triangles) {
      const Eigen::Vector3d& a = positions[t[0]];
      const Eigen::Vector3d& b = positions[t[1]];
      const Eigen::Vector3d& c = positions[t[2]];
      if ((b - a).cross(c - a).dot(a + b + c) < 0.0) std::swap(t[1], t[2]);
    }
  }
  std::shared_ptr<const HalfEdgeMesh> build() const {
    return std::make_shared<const HalfEdgeMesh>(positions, triangles);
  }
};

inline DoubleMesh tetrahedron() {
  DoubleMesh m;
  m.positions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  m.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  m.orientOutward();
  return m;
}

inline DoubleMesh octahedron() {
  DoubleMesh m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  m.orientOutward();
  return m;
}

/// Two apexes over a regular n-gon: apex degree n, equator vertices degree 4.
inline DoubleMesh bipyramid(int n) {
  DoubleMesh m;
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * kPi * i / n;
    m.positions.emplace_back(std::cos(angle), std::sin(angle), 0.0);
  }
  m.positions.emplace_back(0.0, 0.0, 1.0);
  m.positions.emplace_back(0.0, 0.0, -1.0);
  const auto top = static_cast<std::uint32_t>(n);
  const auto bottom = static_cast<std::uint32_t>(n + 1);
  for (int i = 0; i < n; ++i) {
    const auto a = static_cast<std::uint32_t>(i);
    const auto b = static_cast<std::uint32_t>((i + 1) % n);
    m.triangles.push_back({a, b, top});
    m.triangles.push_back({b, a, bottom});
  }
  m.orientOutward();
  return m;
}

/// Icosahedron with vertices on the unit sphere, subdivided `levels` times (midpoints pushed to
/// the sphere; unitIcosphere()).
inline DoubleMesh icosphere(int levels) {
  UnitIcosphere sphere = unitIcosphere(levels);
  return {std::move(sphere.positions), std::move(sphere.triangles)};
}

/// A torus about the z axis with `around` x `across` vertices, every vertex of degree 6 (each
/// quad split along the same diagonal), outward-facing.
inline DoubleMesh torus(double major, double minor, int around, int across) {
  DoubleMesh m;
  for (int i = 0; i < around; ++i) {
    const double u = 2.0 * kPi * i / around;
    for (int j = 0; j < across; ++j) {
      const double v = 2.0 * kPi * j / across;
      m.positions.emplace_back((major + minor * std::cos(v)) * std::cos(u),
                               (major + minor * std::cos(v)) * std::sin(u), minor * std::sin(v));
    }
  }
  const auto index = [&](int i, int j) {
    return static_cast<TriangleMesh::Index>(((i + around) % around) * across +
                                            (j + across) % across);
  };
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < across; ++j) {
      m.triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      m.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  }
  return m;
}

/// Vertex degrees of a triangle list.
inline std::vector<int> degrees(const DoubleMesh& m) {
  std::vector<std::set<std::uint32_t>> neighbors(m.positions.size());
  for (const TriangleMesh::Triangle& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      neighbors[t[k]].insert(t[(k + 1) % 3]);
      neighbors[t[k]].insert(t[(k + 2) % 3]);
    }
  }
  std::vector<int> result;
  for (const auto& n : neighbors) result.push_back(static_cast<int>(n.size()));
  return result;
}

/// A sphere-like closed mesh with vertices of every degree from 3 to 9: the twice subdivided
/// icosphere, edges flipped around chosen vertices (raising one vertex to 9, 8, 7 and lowering
/// others to 4 and 3), then relaxed on the unit sphere (each vertex moved to the normalised mean
/// of its neighbours, 30 times) so the triangles are well shaped.
inline DoubleMesh mixedDegreeMesh() {
  DoubleMesh m = icosphere(2);
  const auto findFace = [&](std::uint32_t a, std::uint32_t b) -> int {
    for (std::size_t f = 0; f < m.triangles.size(); ++f) {
      const auto& t = m.triangles[f];
      for (int k = 0; k < 3; ++k) {
        if (t[k] == a && t[(k + 1) % 3] == b) return static_cast<int>(f);
      }
    }
    return -1;
  };
  const auto third = [&](int f, std::uint32_t a, std::uint32_t b) {
    for (const std::uint32_t v : m.triangles[f]) {
      if (v != a && v != b) return v;
    }
    return a;
  };
  const auto adjacent = [&](std::uint32_t a, std::uint32_t b) { return findFace(a, b) >= 0; };
  // Flips edge a-b (faces (a, b, c), (b, a, d)) to c-d; false when not allowed.
  const auto flip = [&](std::uint32_t a, std::uint32_t b) {
    const int f1 = findFace(a, b);
    const int f2 = findFace(b, a);
    if (f1 < 0 || f2 < 0) return false;
    const std::uint32_t c = third(f1, a, b);
    const std::uint32_t d = third(f2, a, b);
    const std::vector<int> deg = degrees(m);
    if (c == d || adjacent(c, d) || deg[a] <= 3 || deg[b] <= 3) return false;
    m.triangles[f1] = {a, d, c};
    m.triangles[f2] = {d, b, c};
    return true;
  };
  const auto neighborsOf = [&](std::uint32_t v) {
    std::vector<std::uint32_t> result;
    for (const auto& t : m.triangles) {
      for (int k = 0; k < 3; ++k) {
        if (t[k] == v) result.push_back(t[(k + 1) % 3]);
      }
    }
    std::sort(result.begin(), result.end());
    return result;
  };
  // Raise `v` by one: flip the edge opposite v in one of its faces (whose ends keep >= 5).
  const auto raise = [&](std::uint32_t v) {
    for (const std::uint32_t x : neighborsOf(v)) {
      const int f = findFace(v, x);
      const std::uint32_t y = third(f, v, x);
      if (degrees(m)[x] < 6 || degrees(m)[y] < 6) continue;
      if (flip(x, y)) return true;
    }
    return false;
  };
  // Lower `v` by one: flip one of its edges.
  const auto lower = [&](std::uint32_t v) {
    for (const std::uint32_t x : neighborsOf(v)) {
      if (degrees(m)[x] < 6) continue;
      if (flip(v, x)) return true;
    }
    return false;
  };
  // Degree-6 vertices of the level-2 icosphere are 12.., degree 5 are 0..11.
  bool ok = true;
  for (int i = 0; i < 3; ++i) ok = ok && raise(40);   // 6 -> 9
  for (int i = 0; i < 2; ++i) ok = ok && raise(100);  // 6 -> 8
  ok = ok && raise(140);                              // 6 -> 7
  ok = ok && lower(3);                                // 5 -> 4
  for (int i = 0; i < 2; ++i) ok = ok && lower(6);    // 5 -> 3
  EXPECT_TRUE(ok) << "a planned edge flip was not possible";
  for (int iteration = 0; iteration < 30; ++iteration) {
    std::vector<Eigen::Vector3d> next = m.positions;
    for (std::uint32_t v = 0; v < m.positions.size(); ++v) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (const std::uint32_t x : neighborsOf(v)) sum += m.positions[x];
      next[v] = sum.normalized();
    }
    m.positions = std::move(next);
  }
  return m;
}

// ------------------------------------------------------------------------------------------------
// Reference Loop subdivision: edge map, plain rules, face f -> faces 4f..4f+3 as (a, ab, ca),
// (ab, b, bc), (ca, bc, c), (ab, bc, ca).

inline double referenceBeta(int n) {
  const double a = 3.0 / 8.0 + 0.25 * std::cos(2.0 * kPi / n);
  return (5.0 / 8.0 - a * a) / n;
}

inline DoubleMesh referenceSubdivide(const DoubleMesh& m) {
  std::vector<std::set<std::uint32_t>> neighbors(m.positions.size());
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> opposite;
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k];
      const std::uint32_t b = t[(k + 1) % 3];
      neighbors[a].insert(b);
      neighbors[b].insert(a);
      opposite[std::minmax(a, b)].push_back(t[(k + 2) % 3]);
    }
  }
  DoubleMesh fine;
  for (std::uint32_t v = 0; v < m.positions.size(); ++v) {
    const int n = static_cast<int>(neighbors[v].size());
    const double beta = referenceBeta(n);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const std::uint32_t x : neighbors[v]) sum += m.positions[x];
    fine.positions.push_back((1.0 - n * beta) * m.positions[v] + beta * sum);
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edgeVertex;
  const auto edgePoint = [&](std::uint32_t a, std::uint32_t b) {
    const auto key = std::minmax(a, b);
    const auto found = edgeVertex.find(key);
    if (found != edgeVertex.end()) return found->second;
    const auto& opp = opposite.at(key);
    fine.positions.push_back(3.0 / 8.0 * (m.positions[a] + m.positions[b]) +
                             1.0 / 8.0 * (m.positions[opp[0]] + m.positions[opp[1]]));
    const auto index = static_cast<std::uint32_t>(fine.positions.size() - 1);
    edgeVertex.emplace(key, index);
    return index;
  };
  for (const auto& t : m.triangles) {
    const std::uint32_t ab = edgePoint(t[0], t[1]);
    const std::uint32_t bc = edgePoint(t[1], t[2]);
    const std::uint32_t ca = edgePoint(t[2], t[0]);
    fine.triangles.push_back({t[0], ab, ca});
    fine.triangles.push_back({ab, t[1], bc});
    fine.triangles.push_back({ca, bc, t[2]});
    fine.triangles.push_back({ab, bc, ca});
  }
  return fine;
}

/// Loop's limit position of every vertex: (1 - n chi) v + chi (sum of neighbours),
/// chi = 1 / (3 / (8 beta) + n).
inline std::vector<Eigen::Vector3d> referenceLimitPositions(const DoubleMesh& m) {
  std::vector<std::set<std::uint32_t>> neighbors(m.positions.size());
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      neighbors[t[k]].insert(t[(k + 1) % 3]);
      neighbors[t[k]].insert(t[(k + 2) % 3]);
    }
  }
  std::vector<Eigen::Vector3d> limits;
  for (std::uint32_t v = 0; v < m.positions.size(); ++v) {
    const int n = static_cast<int>(neighbors[v].size());
    const double chi = 1.0 / (3.0 / (8.0 * referenceBeta(n)) + n);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const std::uint32_t x : neighbors[v]) sum += m.positions[x];
    limits.push_back((1.0 - n * chi) * m.positions[v] + chi * sum);
  }
  return limits;
}

/// The vertex of `levels`-times subdivided mesh at the dyadic face point (face, (i, j) / 2^levels)
/// (b1 = i / 2^levels, b2 = j / 2^levels), following the sub-face layout down.
inline std::uint32_t dyadicVertex(const std::vector<DoubleMesh>& hierarchy, std::uint32_t face,
                                  long i, long j, int levels) {
  long scale = 1L << levels;
  long b1 = i;
  long b2 = j;
  long b0 = scale - i - j;
  std::uint32_t f = face;
  for (int level = 0; level < levels; ++level) {
    const long half = scale / 2;
    int sub = 3;
    if (b0 >= half) {
      sub = 0;
      b0 -= half;
    } else if (b1 >= half) {
      sub = 1;
      b1 -= half;
    } else if (b2 >= half) {
      sub = 2;
      b2 -= half;
    } else {
      // centre (ab, bc, ca): new b0 = 1 - 2 b2, b1 = 1 - 2 b0, b2 = 1 - 2 b1 in units of scale.
      const long n0 = half - b2;
      const long n1 = half - b0;
      const long n2 = half - b1;
      b0 = n0;
      b1 = n1;
      b2 = n2;
    }
    f = 4 * f + static_cast<std::uint32_t>(sub);
    scale = half;
  }
  const auto& t = hierarchy[static_cast<std::size_t>(levels)].triangles[f];
  if (b0 == scale) return t[0];
  if (b1 == scale) return t[1];
  return t[2];
}

}  // namespace d2vdb::test
