// Independent references for the fitting tests: analytic ellipse and helix distances (dense
// sampling + Newton on the parameter), sampling helpers and a dense reference of the quadratic
// model's step.
#pragma once

#include <Eigen/Core>
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "common/WithThreads.h"
#include "d2vdb/field/Approximant.h"
#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb::test {

inline constexpr double kTwoPi = 6.283185307179586476925;

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

/// The flower-like loop (r cos t, 0.8 r sin t), r = 1 + 0.2 cos 3t: a closed 2D curve with three
/// lobes and concave stretches between them.
inline ParametricCurve threeLobedLoop() {
  const auto radius = [](double t, double& r, double& dr, double& ddr) {
    r = 1.0 + 0.2 * std::cos(3.0 * t);
    dr = -0.6 * std::sin(3.0 * t);
    ddr = -1.8 * std::cos(3.0 * t);
  };
  return {[=](double t) {
            double r, dr, ddr;
            radius(t, r, dr, ddr);
            return Eigen::Vector3d(r * std::cos(t), 0.8 * r * std::sin(t), 0.0);
          },
          [=](double t) {
            double r, dr, ddr;
            radius(t, r, dr, ddr);
            return Eigen::Vector3d(dr * std::cos(t) - r * std::sin(t),
                                   0.8 * (dr * std::sin(t) + r * std::cos(t)), 0.0);
          },
          [=](double t) {
            double r, dr, ddr;
            radius(t, r, dr, ddr);
            return Eigen::Vector3d((ddr - r) * std::cos(t) - 2.0 * dr * std::sin(t),
                                   0.8 * ((ddr - r) * std::sin(t) + 2.0 * dr * std::cos(t)), 0.0);
          },
          0.0,
          kTwoPi,
          true};
}

/// The open 2D wave (t, 0.3 sin(1.25 pi t)), t in [-1, 1].
inline ParametricCurve openWave() {
  const double k = 1.25 * 3.14159265358979323846;
  return {[=](double t) { return Eigen::Vector3d(t, 0.3 * std::sin(k * t), 0.0); },
          [=](double t) { return Eigen::Vector3d(1.0, 0.3 * k * std::cos(k * t), 0.0); },
          [=](double t) { return Eigen::Vector3d(0.0, -0.3 * k * k * std::sin(k * t), 0.0); },
          -1.0,
          1.0,
          false};
}

/// The closed space curve (r cos t, r sin t, 0.3 sin 3t), r = 1 + 0.25 cos 3t.
inline ParametricCurve wavySpaceLoop() {
  const auto radius = [](double t, double& r, double& dr, double& ddr) {
    r = 1.0 + 0.25 * std::cos(3.0 * t);
    dr = -0.75 * std::sin(3.0 * t);
    ddr = -2.25 * std::cos(3.0 * t);
  };
  return {[=](double t) {
            double r, dr, ddr;
            radius(t, r, dr, ddr);
            return Eigen::Vector3d(r * std::cos(t), r * std::sin(t), 0.3 * std::sin(3.0 * t));
          },
          [=](double t) {
            double r, dr, ddr;
            radius(t, r, dr, ddr);
            return Eigen::Vector3d(dr * std::cos(t) - r * std::sin(t),
                                   dr * std::sin(t) + r * std::cos(t), 0.9 * std::cos(3.0 * t));
          },
          [=](double t) {
            double r, dr, ddr;
            radius(t, r, dr, ddr);
            return Eigen::Vector3d((ddr - r) * std::cos(t) - 2.0 * dr * std::sin(t),
                                   (ddr - r) * std::sin(t) + 2.0 * dr * std::cos(t),
                                   -2.7 * std::sin(3.0 * t));
          },
          0.0,
          kTwoPi,
          true};
}

/// How a generated point cloud samples its curve.
enum class Sampling {
  Noisy,       ///< uniform in arc length, Gaussian noise of sigma 0.5 % of the size per coordinate
  Thick,       ///< uniform in arc length, uniform across a band (2D) or tube (3D) of radius 2.5 %
               ///< of the size
  NonUniform,  ///< density 2 + cos(2 pi s / L) along the arc length s (3:1), noise as Noisy
  Clean,       ///< evenly spaced in arc length, no noise
};

/// A point cloud sampled from a known curve, with its noise level sigma per normal direction
/// (world units; 0 for Clean).
struct GeneratedCloud {
  std::vector<Eigen::Vector3d> points;
  double sigma = 0.0;
};

/// `count` points sampled from `curve` (dimension 2 keeps z = 0) as `sampling` says, `size` the
/// curve's size for the noise level, random numbers from std::mt19937(seed).
inline GeneratedCloud generateCloud(const ParametricCurve& curve, int dimension, Sampling sampling,
                                    int count, double size, unsigned seed) {
  const int table = 20000;
  std::vector<double> parameters(table + 1), weight(table + 1, 0.0), arc(table + 1, 0.0);
  for (int i = 0; i <= table; ++i)
    parameters[i] = curve.start + (curve.end - curve.start) * i / table;
  for (int i = 1; i <= table; ++i) {
    arc[i] = arc[i - 1] + (curve.point(parameters[i]) - curve.point(parameters[i - 1])).norm();
  }
  for (int i = 1; i <= table; ++i) {
    const double s = 0.5 * (arc[i] + arc[i - 1]);
    const double density =
        sampling == Sampling::NonUniform ? 2.0 + std::cos(kTwoPi * s / arc.back()) : 1.0;
    weight[i] = weight[i - 1] + density * (arc[i] - arc[i - 1]);
  }
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double sigma = 0.005 * size;
  const double thickness = 0.025 * size;
  GeneratedCloud cloud;
  cloud.sigma = sampling == Sampling::Clean   ? 0.0
                : sampling == Sampling::Thick ? thickness / (dimension == 2 ? std::sqrt(3.0) : 2.0)
                                              : sigma;
  for (int i = 0; i < count; ++i) {
    // Inverse of the cumulative density by bisection and linear interpolation in the table.
    const double w =
        (sampling == Sampling::Clean ? (i + 0.5) / count : uniform(engine)) * weight.back();
    const std::size_t j = static_cast<std::size_t>(std::max<std::ptrdiff_t>(
        1, std::lower_bound(weight.begin(), weight.end(), w) - weight.begin()));
    const double f = (w - weight[j - 1]) / std::max(1e-300, weight[j] - weight[j - 1]);
    const double t = parameters[j - 1] + f * (parameters[j] - parameters[j - 1]);
    Eigen::Vector3d p = curve.point(t);
    const Eigen::Vector3d tangent = curve.first(t).normalized();
    if (sampling == Sampling::Thick) {
      if (dimension == 2) {
        p += (2.0 * uniform(engine) - 1.0) * thickness *
             Eigen::Vector3d(-tangent.y(), tangent.x(), 0.0);
      } else {
        const Eigen::Vector3d n1 = tangent.unitOrthogonal();
        const Eigen::Vector3d n2 = tangent.cross(n1);
        double a = 1.0, b = 1.0;
        while (a * a + b * b > 1.0)
          a = 2.0 * uniform(engine) - 1.0, b = 2.0 * uniform(engine) - 1.0;
        p += thickness * (a * n1 + b * n2);
      }
    } else if (sampling != Sampling::Clean) {
      p += sigma *
           Eigen::Vector3d(gauss(engine), gauss(engine), dimension == 3 ? gauss(engine) : 0.0);
    }
    cloud.points.push_back(p);
  }
  return cloud;
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

/// RMS of the reference distance from `count` samples of the B-spline to the curve, leaving out
/// the samples whose nearest curve point is an end of an open curve (the part of the fit that
/// runs on past the curve's ends: noisy data end up to a few sigma beyond them). `overhang` gets
/// the fraction of samples left out.
inline double splineToCurveInterior(const BSplineCurve& spline, const ParametricCurve& curve,
                                    int count, double* overhang = nullptr) {
  double sum = 0.0;
  int used = 0;
  const std::vector<Eigen::Vector3d> points = spline.sample(count);
  for (const Eigen::Vector3d& p : points) {
    double t = 0.0;
    const double d = referenceDistance(curve, p, &t);
    if (!curve.periodic && (t <= curve.start || t >= curve.end)) continue;
    sum += d * d;
    ++used;
  }
  if (overhang != nullptr) *overhang = 1.0 - static_cast<double>(used) / points.size();
  return used > 0 ? std::sqrt(sum / used) : 0.0;
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

/// The minimiser c of (1/N) sum_k Q_k(J_k (P + c)) + sum_a (P + c)_a^T S (P + c)_a (a over the
/// coordinates) by a dense solve of its normal equations: the reference for QuadraticModel::solve.
/// `jacobian(k)` is the 3 x 3n derivative J_k of sensor k's position by the n = points.size()
/// control points P, `forms` the N sensors' quadratic forms Q_k and `smoothing` the n x n matrix S.
template <typename Jacobian>
std::vector<Eigen::Vector3d> denseModelStep(int sensorCount, Jacobian&& jacobian,
                                            const std::vector<QuadraticForm>& forms,
                                            const Eigen::SparseMatrix<double>& smoothing,
                                            const std::vector<Eigen::Vector3d>& points) {
  const int n = static_cast<int>(points.size());
  Eigen::MatrixXd hessian = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  Eigen::VectorXd right = Eigen::VectorXd::Zero(3 * n);
  const double inverseCount = 1.0 / sensorCount;
  for (int k = 0; k < sensorCount; ++k) {
    const Eigen::MatrixXd j = jacobian(k);
    const QuadraticForm& form = forms[static_cast<std::size_t>(k)];
    hessian += inverseCount * j.transpose() * form.A * j;
    right += inverseCount * j.transpose() * form.b;
  }
  const Eigen::MatrixXd dense = Eigen::MatrixXd(smoothing);
  Eigen::VectorXd current(3 * n);
  for (int i = 0; i < n; ++i) {
    current.segment<3>(3 * i) = points[static_cast<std::size_t>(i)];
    for (int j = 0; j < n; ++j) {
      hessian.block<3, 3>(3 * i, 3 * j) += dense(i, j) * Eigen::Matrix3d::Identity();
    }
  }
  const Eigen::VectorXd target = hessian.ldlt().solve(right);
  std::vector<Eigen::Vector3d> step(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    step[static_cast<std::size_t>(i)] = target.segment<3>(3 * i) - current.segment<3>(3 * i);
  }
  return step;
}

}  // namespace d2vdb::test
