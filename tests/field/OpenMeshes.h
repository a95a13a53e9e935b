// Generated open and non-manifold test meshes with known solids: a sphere cut by a plane (a wide
// planar hole), a flat disc, a sphere with curved junk flaps inside.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <vector>

#include "common/Icosphere.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::test {

inline constexpr double kOpenMeshPi = 3.14159265358979323846;

/// unitIcosphere(levels) as a TriangleMesh (float positions).
inline TriangleMesh unitIcosphereMesh(int levels) {
  const UnitIcosphere unit = unitIcosphere(levels);
  TriangleMesh mesh;
  for (const Eigen::Vector3d& p : unit.positions) mesh.positions.push_back(p.cast<float>());
  mesh.triangles = unit.triangles;
  return mesh;
}

/// The unit sphere as latitude rings from the south pole up to the ring at height `top` (a
/// planar loop, left open when top < 1), `segments` vertices per ring, wound outward.
inline TriangleMesh makeCutSphere(double top, int rings, int segments) {
  TriangleMesh mesh;
  mesh.positions.emplace_back(0.0f, 0.0f, -1.0f);
  const double last = std::acos(-top);  // polar angle from the south pole of the top ring
  for (int k = 1; k <= rings; ++k) {
    const double phi = last * k / rings;
    for (int j = 0; j < segments; ++j) {
      const double alpha = 2.0 * kOpenMeshPi * j / segments;
      mesh.positions.emplace_back(static_cast<float>(std::sin(phi) * std::cos(alpha)),
                                  static_cast<float>(std::sin(phi) * std::sin(alpha)),
                                  static_cast<float>(-std::cos(phi)));
    }
  }
  const auto at = [segments](int ring, int j) {
    return static_cast<TriangleMesh::Index>(1 + (ring - 1) * segments + (j % segments));
  };
  for (int j = 0; j < segments; ++j) mesh.triangles.push_back({0, at(1, j + 1), at(1, j)});
  for (int k = 1; k < rings; ++k) {
    for (int j = 0; j < segments; ++j) {
      mesh.triangles.push_back({at(k, j), at(k, j + 1), at(k + 1, j + 1)});
      mesh.triangles.push_back({at(k, j), at(k + 1, j + 1), at(k + 1, j)});
    }
  }
  return mesh;
}

/// A flat disc of `radius` at height `z` (a fan of `segments` triangles around its centre),
/// wound counter-clockwise seen from +z.
inline TriangleMesh makeDisc(double radius, int segments, double z) {
  TriangleMesh disc;
  disc.positions.emplace_back(0.0f, 0.0f, static_cast<float>(z));
  for (int j = 0; j < segments; ++j) {
    const double alpha = 2.0 * kOpenMeshPi * j / segments;
    disc.positions.emplace_back(static_cast<float>(radius * std::cos(alpha)),
                                static_cast<float>(radius * std::sin(alpha)),
                                static_cast<float>(z));
    disc.triangles.push_back({0, static_cast<TriangleMesh::Index>(1 + j),
                              static_cast<TriangleMesh::Index>(1 + (j + 1) % segments)});
  }
  return disc;
}

/// The unit sphere (closed icosphere) with curved flaps inside: copies, scaled by `scale`, of
/// the patches of the sphere within `reach` of each of `centres`, wound inward and left open.
/// Beside each flap's concave side the winding number is below 1/2 (a lens of "outside").
inline TriangleMesh makeSphereWithInwardFlaps(const std::vector<Eigen::Vector3f>& centers,
                                              float reach, float scale) {
  const TriangleMesh sphere = unitIcosphereMesh(4);
  TriangleMesh mesh = sphere;
  for (const Eigen::Vector3f& f : centers) {
    for (const TriangleMesh::Triangle& t : sphere.triangles) {
      const Eigen::Vector3f centroid =
          (sphere.positions[t[0]] + sphere.positions[t[1]] + sphere.positions[t[2]]) / 3.0f;
      if ((centroid - f).norm() >= reach) continue;
      const auto base = static_cast<TriangleMesh::Index>(mesh.positions.size());
      for (const TriangleMesh::Index corner : t) {
        mesh.positions.push_back(scale * sphere.positions[corner]);
      }
      mesh.triangles.push_back({base, base + 2, base + 1});
    }
  }
  return mesh;
}

}  // namespace d2vdb::test
