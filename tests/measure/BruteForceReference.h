// Independent brute-force references for point projection and curve Hausdorff distances: dense
// uniform sampling of every knot span plus golden-section refinement of every sampled local
// extremum that could be the global one. Uses only BSplineCurve::evaluate() and its knots, none of
// the measure module. Slow on purpose; used by the tests and by tools/bench/bench_hausdorff.cc.
#pragma once

#include <tbb/parallel_for.h>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb::test {

/// Result of a brute-force extremum search: where and what value.
struct BruteExtremum {
  double parameter = 0.0;
  double value = 0.0;
};

/// Minimises f on [a, b] by golden-section search down to a bracket of a few ulps; returns the
/// best point seen (the ends included).
template <typename Function>
BruteExtremum goldenSectionMinimum(const Function& f, double a, double b) {
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  BruteExtremum best{a, f(a)};
  const double fb = f(b);
  if (fb < best.value) best = {b, fb};
  double x1 = b - ratio * (b - a);
  double x2 = a + ratio * (b - a);
  double f1 = f(x1);
  double f2 = f(x2);
  for (int iteration = 0; iteration < 200; ++iteration) {
    if (b - a <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(a))) break;
    if (f1 <= f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - ratio * (b - a);
      f1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + ratio * (b - a);
      f2 = f(x2);
    }
  }
  if (f1 < best.value) best = {x1, f1};
  if (f2 < best.value) best = {x2, f2};
  return best;
}

/// `samplesPerSpan` + 1 parameters per non-empty knot span, uniform within each span, all
/// breakpoints included, ascending.
inline std::vector<double> denseParameters(const BSplineCurve& curve, int samplesPerSpan) {
  const std::vector<double> breaks = curve.knots().breakpoints();
  std::vector<double> parameters;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    for (int k = 0; k < samplesPerSpan; ++k) {
      parameters.push_back(breaks[i] + (breaks[i + 1] - breaks[i]) * k / samplesPerSpan);
    }
  }
  parameters.push_back(breaks.back());
  return parameters;
}

/// Optimises f over the samples: the sampled values, then golden-section refinement between the
/// neighbours of every sampled local optimum whose value is within `margin` of the best sample.
/// `sign` = +1 minimises, -1 maximises. With `parallel`, the samples and the refinements run in
/// parallel (TBB), with the same result.
template <typename Function>
BruteExtremum refineSampled(const Function& f, const std::vector<double>& parameters, double margin,
                            int sign, bool parallel = false) {
  const auto forEach = [parallel](std::size_t count, const auto& body) {
    if (parallel) {
      tbb::parallel_for(std::size_t{0}, count, body);
    } else {
      for (std::size_t i = 0; i < count; ++i) body(i);
    }
  };
  std::vector<double> values(parameters.size());
  forEach(parameters.size(), [&](std::size_t i) { values[i] = sign * f(parameters[i]); });
  const double bestSample = *std::min_element(values.begin(), values.end());
  const std::size_t last = parameters.size() - 1;
  std::vector<std::size_t> optima;
  for (std::size_t i = 0; i <= last; ++i) {
    const bool leftOk = i == 0 || values[i] <= values[i - 1];
    const bool rightOk = i == last || values[i] <= values[i + 1];
    if (leftOk && rightOk && values[i] <= bestSample + margin) optima.push_back(i);
  }
  std::vector<BruteExtremum> refined(optima.size());
  forEach(optima.size(), [&](std::size_t k) {
    const std::size_t i = optima[k];
    const double a = parameters[i == 0 ? 0 : i - 1];
    const double b = parameters[i == last ? last : i + 1];
    const auto signedF = [&](double t) { return sign * f(t); };
    refined[k] = goldenSectionMinimum(signedF, a, b);
  });
  BruteExtremum best{0.0, std::numeric_limits<double>::infinity()};
  for (const BruteExtremum& candidate : refined) {
    if (candidate.value < best.value) best = candidate;
  }
  best.value *= sign;
  return best;
}

/// Largest sampled speed |C(t_{i+1}) - C(t_i)| / (t_{i+1} - t_i): a Lipschitz estimate for the
/// refinement margins.
inline double sampledSpeed(const BSplineCurve& curve, const std::vector<double>& parameters) {
  double speed = 0.0;
  for (std::size_t i = 0; i + 1 < parameters.size(); ++i) {
    const double step = parameters[i + 1] - parameters[i];
    speed = std::max(
        speed, (curve.evaluate(parameters[i + 1]) - curve.evaluate(parameters[i])).norm() / step);
  }
  return speed;
}

/// Brute-force nearest point: parameter and distance (not squared).
class BruteForceProjector {
 public:
  explicit BruteForceProjector(const BSplineCurve& curve, int samplesPerSpan = 64)
      : curve_(curve), parameters_(denseParameters(curve, samplesPerSpan)) {
    double spacing = 0.0;
    for (std::size_t i = 0; i + 1 < parameters_.size(); ++i) {
      spacing = std::max(spacing, parameters_[i + 1] - parameters_[i]);
    }
    margin_ = 4.0 * sampledSpeed(curve, parameters_) * spacing;
  }

  BruteExtremum nearest(const Eigen::Vector3d& point) const {
    const auto distance = [&](double t) { return (curve_.evaluate(t) - point).norm(); };
    return refineSampled(distance, parameters_, margin_, +1);
  }

 private:
  const BSplineCurve& curve_;
  std::vector<double> parameters_;
  double margin_ = 0.0;
};

/// Brute-force one-sided Hausdorff distance h(from -> to): parameter on `from` and the value.
/// `parallel` spreads the samples of `from` over TBB threads.
inline BruteExtremum bruteForceHausdorff(const BSplineCurve& from, const BSplineCurve& to,
                                         int samplesPerSpan = 64, bool parallel = false) {
  const BruteForceProjector projector(to, samplesPerSpan);
  const std::vector<double> parameters = denseParameters(from, samplesPerSpan);
  double spacing = 0.0;
  for (std::size_t i = 0; i + 1 < parameters.size(); ++i) {
    spacing = std::max(spacing, parameters[i + 1] - parameters[i]);
  }
  const double margin = 4.0 * sampledSpeed(from, parameters) * spacing;
  const auto oneSided = [&](double u) { return projector.nearest(from.evaluate(u)).value; };
  return refineSampled(oneSided, parameters, margin, -1, parallel);
}

}  // namespace d2vdb::test
