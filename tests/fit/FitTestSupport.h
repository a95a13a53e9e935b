// Independent references for the fitting tests: analytic ellipse and helix distances (dense
// sampling + Newton on the parameter), thread-count control and sampling helpers.
#pragma once

#include <tbb/global_control.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb::test {

inline constexpr double kTwoPi = 6.283185307179586476925;

/// Runs `work` with TBB limited to `threads` threads and returns its result.
template <typename Work>
auto withThreads(int threads, Work&& work) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
  return work();
}

/// A parametric curve with first and second derivatives, for reference distances.
struct ParametricCurve {
  std::function<Eigen::Vector3d(double)> point;
  std::function<Eigen::Vector3d(double)> first;
  std::function<Eigen::Vector3d(double)> second;
  double start = 0.0;
  double end = 1.0;
  bool periodic = false;
};

inline ParametricCurve ellipseCurve(double a, double b) {
  return {[=](double t) { return Eigen::Vector3d(a * std::cos(t), b * std::sin(t), 0.0); },
          [=](double t) { return Eigen::Vector3d(-a * std::sin(t), b * std::cos(t), 0.0); },
          [=](double t) { return Eigen::Vector3d(-a * std::cos(t), -b * std::sin(t), 0.0); },
          0.0,
          kTwoPi,
          true};
}

/// Helix (R cos t, R sin t, h t), t in [0, turns 2 pi].
inline ParametricCurve helixCurve(double radius, double pitch, double turns) {
  return {
      [=](double t) {
        return Eigen::Vector3d(radius * std::cos(t), radius * std::sin(t), pitch * t);
      },
      [=](double t) { return Eigen::Vector3d(-radius * std::sin(t), radius * std::cos(t), pitch); },
      [=](double t) { return Eigen::Vector3d(-radius * std::cos(t), -radius * std::sin(t), 0.0); },
      0.0,
      turns * kTwoPi,
      false};
}

/// Distance from p to the curve: the best of `samples` uniform parameters, refined by Newton on
/// (C(t) - p) . C'(t) = 0 (clamped to the interval for open curves). Returns the parameter too.
inline double referenceDistance(const ParametricCurve& curve, const Eigen::Vector3d& p,
                                double* parameter = nullptr, int samples = 4096) {
  double bestT = curve.start;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= samples; ++i) {
    const double t = curve.start + (curve.end - curve.start) * i / samples;
    const double d = (curve.point(t) - p).squaredNorm();
    if (d < best) best = d, bestT = t;
  }
  double t = bestT;
  for (int iteration = 0; iteration < 30; ++iteration) {
    const Eigen::Vector3d r = curve.point(t) - p;
    const double f = r.dot(curve.first(t));
    const double df = curve.first(t).squaredNorm() + r.dot(curve.second(t));
    if (df <= 0.0) break;
    double next = t - f / df;
    if (!curve.periodic) next = std::clamp(next, curve.start, curve.end);
    if (std::abs(next - t) < 1e-15) break;
    t = next;
  }
  const double refined = (curve.point(t) - p).squaredNorm();
  if (refined < best) best = refined, bestT = t;
  if (parameter != nullptr) *parameter = bestT;
  return std::sqrt(best);
}

/// `count` points of the curve, uniform in parameter (periodic: the last point is not repeated).
inline std::vector<Eigen::Vector3d> samplePoints(const ParametricCurve& curve, int count) {
  std::vector<Eigen::Vector3d> points;
  const int divisions = curve.periodic ? count : count - 1;
  for (int i = 0; i < count; ++i) {
    points.push_back(curve.point(curve.start + (curve.end - curve.start) * i / divisions));
  }
  return points;
}

/// Max and RMS of the reference distance from `count` samples of the B-spline to the curve.
struct DistanceStats {
  double max = 0.0;
  double rms = 0.0;
};
inline DistanceStats splineToCurve(const BSplineCurve& spline, const ParametricCurve& curve,
                                   int count = 1000) {
  DistanceStats stats;
  const std::vector<Eigen::Vector3d> points = spline.sample(count);
  for (const Eigen::Vector3d& p : points) {
    const double d = referenceDistance(curve, p);
    stats.max = std::max(stats.max, d);
    stats.rms += d * d;
  }
  stats.rms = std::sqrt(stats.rms / static_cast<double>(points.size()));
  return stats;
}

/// Largest distance from any point of `points` to the nearest of `dense` samples of the spline
/// (brute force), refined by Newton on the spline's derivatives.
inline double pointsToSpline(const std::vector<Eigen::Vector3d>& points, const BSplineCurve& spline,
                             int dense = 4000) {
  const ParameterInterval domain = spline.domain();
  ParametricCurve curve{[&](double t) { return spline.evaluate(t); },
                        [&](double t) { return spline.derivatives(t).first; },
                        [&](double t) { return spline.derivatives(t).second; },
                        domain.start,
                        domain.end,
                        spline.isClosed()};
  double worst = 0.0;
  for (const Eigen::Vector3d& p : points) {
    worst = std::max(worst, referenceDistance(curve, p, nullptr, dense));
  }
  return worst;
}

}  // namespace d2vdb::test
