// Shared helpers of the support-function tests: the ellipsoid and the hyperboloid with their exact
// support functions, random unit vectors, thread-count control.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "common/WithThreads.h"
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/mesh/TriangleMesh.h"
#include "d2vdb/support/SupportFit.h"

namespace d2vdb::test {

/// `count` unit vectors, uniformly distributed, from a fixed seed.
inline std::vector<Eigen::Vector3d> randomUnitVectors(std::size_t count, unsigned seed) {
  std::mt19937_64 engine(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Eigen::Vector3d> out;
  out.reserve(count);
  while (out.size() < count) {
    const Eigen::Vector3d v(gauss(engine), gauss(engine), gauss(engine));
    if (v.norm() > 1e-6) out.push_back(v.normalized());
  }
  return out;
}

/// The ellipsoid x^T A^-2 x = 1, A = diag(a, b, c): h(n) = |A n|, x_h(n) = A^2 n / |A n|.
struct Ellipsoid {
  double a = 2.0;
  double b = 1.5;
  double c = 1.0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();

  double support(const Eigen::Vector3d& n) const {
    return Eigen::Vector3d(a * n.x(), b * n.y(), c * n.z()).norm() + center.dot(n);
  }
  Eigen::Vector3d point(const Eigen::Vector3d& n) const {
    const Eigen::Vector3d an(a * n.x(), b * n.y(), c * n.z());
    return center + Eigen::Vector3d(a * an.x(), b * an.y(), c * an.z()) / an.norm();
  }
  /// Oriented samples x_h(n_i), n_i at `count` random normals.
  OrientedSamples samples(std::size_t count, unsigned seed) const {
    OrientedSamples s;
    s.normals = randomUnitVectors(count, seed);
    for (const auto& n : s.normals) s.points.push_back(point(n));
    return s;
  }
};

}  // namespace d2vdb::test

namespace d2vdb::test {

/// Signed distance from p to the ellipsoid (negative inside), by bisection on the Lagrange
/// parameter t of the closest point x_i = e_i^2 p_i / (t + e_i^2), the unique root in
/// (-min e_i^2, inf) of sum (e_i p_i / (t + e_i^2))^2 = 1 (Eberly, "Distance from a point to an
/// ellipse, an ellipsoid, or a hyperellipsoid", 2013).
inline double signedDistanceToEllipsoid(const Ellipsoid& e, const Eigen::Vector3d& point) {
  const Eigen::Vector3d p = point - e.center;
  const double axes[3] = {e.a, e.b, e.c};
  double smallest = std::min({e.a, e.b, e.c});
  // Nudge coordinates off the symmetry planes: the root is then unique and simple.
  double q[3];
  for (int i = 0; i < 3; ++i) q[i] = std::abs(p[i]) < 1e-12 ? 1e-12 : p[i];
  const auto f = [&](double t) {
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double r = axes[i] * q[i] / (t + axes[i] * axes[i]);
      sum += r * r;
    }
    return sum - 1.0;
  };
  double lo = -smallest * smallest;
  double hi = 1.0;
  while (f(hi) > 0.0) hi *= 2.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (f(mid) > 0.0 ? lo : hi) = mid;
  }
  const double t = 0.5 * (lo + hi);
  Eigen::Vector3d closest;
  for (int i = 0; i < 3; ++i) closest[i] = axes[i] * axes[i] * q[i] / (t + axes[i] * axes[i]);
  const double inside =
      (p.x() / e.a) * (p.x() / e.a) + (p.y() / e.b) * (p.y() / e.b) + (p.z() / e.c) * (p.z() / e.c);
  const double distance = (Eigen::Vector3d(q[0], q[1], q[2]) - closest).norm();
  return inside < 1.0 ? -distance : distance;
}

/// What checkClosedMesh() finds.
struct ClosedMeshCheck {
  /// Every directed edge occurs exactly once and so does its reverse: the mesh is closed,
  /// edge-manifold and consistently oriented.
  bool closedAndOriented = true;
  /// The signed volume it encloses (divergence theorem; positive when the triangles face out).
  double volume = 0.0;
};

/// Counts the mesh's directed edges and sums the signed volumes of the tetrahedra from the origin
/// to its triangles.
inline ClosedMeshCheck checkClosedMesh(const TriangleMesh& mesh) {
  std::map<std::pair<TriangleMesh::Index, TriangleMesh::Index>, int> directed;
  ClosedMeshCheck check;
  for (const auto& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{tri[k], tri[(k + 1) % 3]}];
    const Eigen::Vector3d a = mesh.positions[tri[0]].cast<double>();
    const Eigen::Vector3d b = mesh.positions[tri[1]].cast<double>();
    const Eigen::Vector3d c = mesh.positions[tri[2]].cast<double>();
    check.volume += a.dot(b.cross(c)) / 6.0;
  }
  for (const auto& edge : directed) {
    if (edge.second != 1 || directed.count({edge.first.second, edge.first.first}) != 1) {
      check.closedAndOriented = false;
    }
  }
  return check;
}

/// The one-sheeted hyperboloid x^2 + y^2 - z^2 = 1, |z| <= zMax, as an outward-oriented grid
/// mesh (angle steps x height steps) with exact unit normals (x, y, -z) / |.|. Its support
/// function is sqrt(n_x^2 + n_y^2 - n_z^2); its principal radii are sqrt(1 + 2 z^2) (along the
/// circles) and -(1 + 2 z^2)^(3/2) (along the meridians).
inline TriangleMesh hyperboloidPatch(int angles, int heights, double zMax) {
  TriangleMesh mesh;
  for (int i = 0; i < angles; ++i) {
    const double theta = 2.0 * kPi * i / angles;
    for (int j = 0; j < heights; ++j) {
      const double z = -zMax + 2.0 * zMax * j / (heights - 1);
      const double rho = std::sqrt(1.0 + z * z);
      const Eigen::Vector3d p(rho * std::cos(theta), rho * std::sin(theta), z);
      mesh.positions.push_back(p.cast<float>());
      mesh.normals.push_back(Eigen::Vector3d(p.x(), p.y(), -p.z()).normalized().cast<float>());
    }
  }
  const auto index = [&](int i, int j) {
    return static_cast<TriangleMesh::Index>((i % angles) * heights + j);
  };
  for (int i = 0; i < angles; ++i) {
    for (int j = 0; j + 1 < heights; ++j) {
      mesh.triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      mesh.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  }
  return mesh;
}

}  // namespace d2vdb::test
