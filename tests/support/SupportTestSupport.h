// Shared helpers of the support-function tests: the ellipsoid and the hyperboloid with their exact
// support functions, random unit vectors, thread-count control.
#pragma once

#include <tbb/global_control.h>

#include <Eigen/Core>

#include <cmath>
#include <random>
#include <vector>

#include "d2vdb/support/SupportFit.h"

namespace d2vdb::test {

constexpr double kPi = 3.14159265358979323846;

/// Runs `work` with TBB limited to `threads` threads and returns its result.
template <typename Work>
auto withThreads(int threads, Work&& work) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
  return work();
}

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
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();

  double support(const Eigen::Vector3d& n) const {
    return Eigen::Vector3d(a * n.x(), b * n.y(), c * n.z()).norm() + centre.dot(n);
  }
  Eigen::Vector3d point(const Eigen::Vector3d& n) const {
    const Eigen::Vector3d an(a * n.x(), b * n.y(), c * n.z());
    return centre + Eigen::Vector3d(a * an.x(), b * an.y(), c * an.z()) / an.norm();
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
