#include "d2vdb/measure/detail/BernsteinRoots.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

// An interval [start, end] of the original parameter that holds a root or a cluster of roots.
struct RootInterval {
  double start;
  double end;
  bool polished;  // a single simple root found by Newton: start == end is the root
};

// Shared state of one root search.
struct Search {
  double noise;  // coefficients with |c| <= noise are indistinguishable from zero
  RootIsolationOptions options;
  std::vector<RootInterval> found;
  bool depthLimitReached = false;
};

int signOf(double value) {
  return (value > 0.0) - (value < 0.0);
}

// Number of sign changes among the non-zero coefficients (Descartes' bound for Bernstein form).
int signChanges(const BernsteinPolynomial& f) {
  int changes = 0;
  int previous = 0;
  for (int i = 0; i <= f.degree(); ++i) {
    const int sign = signOf(f.coefficient(i));
    if (sign == 0) continue;
    if (previous != 0 && sign != previous) ++changes;
    previous = sign;
  }
  return changes;
}

// The part [low, high] of [0, 1] where the convex hull of the control points (i / n, c_i) meets
// the band |y| <= noise; low > high when it does not.
void clipToBand(const BernsteinPolynomial& f, double noise, double& low, double& high) {
  const int n = f.degree();
  low = std::numeric_limits<double>::infinity();
  high = -std::numeric_limits<double>::infinity();
  const auto include = [&](double s) {
    low = std::min(low, s);
    high = std::max(high, s);
  };
  // Every hull edge joins two control points, so scanning all pairs covers the hull's boundary.
  for (int i = 0; i <= n; ++i) {
    const double si = n == 0 ? 0.5 : static_cast<double>(i) / n;
    const double ci = f.coefficient(i);
    if (std::abs(ci) <= noise) include(si);
    for (int j = i + 1; j <= n; ++j) {
      const double sj = static_cast<double>(j) / n;
      const double cj = f.coefficient(j);
      if (cj == ci) continue;  // parallel to the band: only its end points can be inside
      const double lambdaA = (-noise - ci) / (cj - ci);
      const double lambdaB = (noise - ci) / (cj - ci);
      const double from = std::max(0.0, std::min(lambdaA, lambdaB));
      const double to = std::min(1.0, std::max(lambdaA, lambdaB));
      if (from <= to) {
        include(si + from * (sj - si));
        include(si + to * (sj - si));
      }
    }
  }
}

// f(t) and f'(t) from one de Casteljau pass (the spline module evaluates values only): the
// last level's two values b0, b1 give f = (1 - t) b0 + t b1 and f' = n (b1 - b0).
struct ValueAndSlope {
  double value;
  double slope;
};

ValueAndSlope evaluateWithSlope(const BernsteinPolynomial& f, double t) {
  const int n = f.degree();
  if (n == 0) return {f.coefficient(0), 0.0};
  std::array<double, kMaxBernsteinDegree + 1> work{};
  for (int i = 0; i <= n; ++i) work[static_cast<std::size_t>(i)] = f.coefficient(i);
  for (int level = 1; level < n; ++level) {
    for (int i = 0; i <= n - level; ++i) {
      work[static_cast<std::size_t>(i)] =
          (1.0 - t) * work[static_cast<std::size_t>(i)] + t * work[static_cast<std::size_t>(i + 1)];
    }
  }
  return {(1.0 - t) * work[0] + t * work[1], n * (work[1] - work[0])};
}

// The single root of f in (0, 1) when f(0) and f(1) have opposite signs and one sign change:
// Newton steps, falling back to bisection whenever a step leaves the current bracket. Stops when
// |f| is within the rounding error of its evaluation, a Newton step is below 1e-9 (the next one
// would be below rounding), or the bracket is a few ulps.
double bracketedNewton(const BernsteinPolynomial& f) {
  const double roundingFloor =
      4.0 * (f.degree() + 1) * kEpsilon * f.coefficients().cwiseAbs().maxCoeff();
  double low = 0.0;
  double high = 1.0;
  const int lowSign = signOf(f.coefficient(0));
  // Regula falsi start, the chord's root.
  const double first = f.coefficient(0);
  const double last = f.coefficient(f.degree());
  double x = first / (first - last);
  for (int iteration = 0; iteration < 200; ++iteration) {
    const auto [value, derivative] = evaluateWithSlope(f, x);
    if (std::abs(value) <= roundingFloor) return x;
    if (signOf(value) == lowSign) {
      low = x;
    } else {
      high = x;
    }
    if (high - low <= 4.0 * kEpsilon) break;
    double next = derivative != 0.0 ? x - value / derivative : 0.5 * (low + high);
    const bool newtonStep = next > low && next < high;
    if (!newtonStep) next = 0.5 * (low + high);
    // Quadratic convergence: after a Newton step this small the next error is below rounding.
    if (std::abs(next - x) <= (newtonStep ? 1e-9 : 2.0 * kEpsilon)) return next;
    x = next;
  }
  return std::clamp(x, 0.0, 1.0);
}

// A root of f reported by a cluster [start, end] (a simple root at a subdivision point, or a
// multiple root): Newton steps from the midpoint on the whole polynomial, kept while they stay
// within the cluster (widened by the tolerance) and do not increase |f|.
double polishCluster(const BernsteinPolynomial& f, double start, double end, double tolerance) {
  const double low = std::max(0.0, start - tolerance);
  const double high = std::min(1.0, end + tolerance);
  double x = 0.5 * (start + end);
  ValueAndSlope current = evaluateWithSlope(f, x);
  for (int iteration = 0; iteration < 8 && current.value != 0.0; ++iteration) {
    if (current.slope == 0.0) break;
    const double next = x - current.value / current.slope;
    if (!(next >= low && next <= high)) break;
    const ValueAndSlope candidate = evaluateWithSlope(f, next);
    if (std::abs(candidate.value) > std::abs(current.value)) break;
    const bool settled = next == x;
    x = next;
    current = candidate;
    if (settled) break;
  }
  return x;
}

void isolate(const BernsteinPolynomial& f, double start, double end, int depth, Search& search) {
  const double width = end - start;
  const double minimum = f.minCoefficient();
  const double maximum = f.maxCoefficient();
  if (minimum > search.noise || maximum < -search.noise) return;  // convex-hull pruning
  const double first = f.coefficient(0);
  const double last = f.coefficient(f.degree());
  const bool endsClear = std::abs(first) > search.noise && std::abs(last) > search.noise;
  if (endsClear && signOf(first) != signOf(last) && signChanges(f) == 1) {
    const double root = start + bracketedNewton(f) * width;
    search.found.push_back({root, root, true});
    return;
  }
  const bool flat = std::max(std::abs(minimum), std::abs(maximum)) <= search.noise;
  if (flat || width <= search.options.parameterTolerance || depth >= search.options.maxDepth) {
    if (depth >= search.options.maxDepth && !flat) search.depthLimitReached = true;
    search.found.push_back({start, end, false});
    return;
  }
  double low = 0.0;
  double high = 1.0;
  clipToBand(f, search.noise, low, high);
  if (low > high) return;
  // Widen by a few ulps of the interval so rounding in the clip never loses a root.
  low = std::max(0.0, low - 8.0 * kEpsilon);
  high = std::min(1.0, high + 8.0 * kEpsilon);
  if (high - low <= 0.5) {
    if (low > 0.0 || high < 1.0) {
      if (high - low <= 0.0) {
        search.found.push_back({start + low * width, start + low * width, false});
        return;
      }
      isolate(f.restricted(low, high), start + low * width, start + high * width, depth + 1,
              search);
      return;
    }
  }
  const auto [left, right] = f.subdivide(0.5);
  const double middle = start + 0.5 * width;
  isolate(left, start, middle, depth + 1, search);
  isolate(right, middle, end, depth + 1, search);
}

}  // namespace

BernsteinRootSet findBernsteinRoots(const BernsteinPolynomial& f,
                                    const RootIsolationOptions& options) {
  if (!(options.parameterTolerance > 0.0) || options.maxDepth < 1) {
    throw InputError("root isolation: parameterTolerance must be > 0 and maxDepth >= 1 (got " +
                     std::to_string(options.parameterTolerance) + " and " +
                     std::to_string(options.maxDepth) + ")");
  }
  BernsteinRootSet result;
  const double scale = f.coefficients().cwiseAbs().maxCoeff();
  if (scale == 0.0) {
    result.identicallyZero = true;
    return result;
  }
  Search search{64.0 * (f.degree() + 1) * kEpsilon * scale, options, {}, false};
  isolate(f, 0.0, 1.0, 0, search);
  result.depthLimitReached = search.depthLimitReached;

  // The recursion visits intervals in ascending order; merge touching ones into one root.
  std::vector<RootInterval>& found = search.found;
  const double gap = 2.0 * options.parameterTolerance;
  for (std::size_t i = 0; i < found.size();) {
    std::size_t j = i;
    double groupEnd = found[i].end;
    double polishedRoot = found[i].polished ? found[i].start : -1.0;
    while (j + 1 < found.size() && found[j + 1].start <= groupEnd + gap) {
      ++j;
      groupEnd = std::max(groupEnd, found[j].end);
      if (found[j].polished && polishedRoot < 0.0) polishedRoot = found[j].start;
    }
    const double root = polishedRoot >= 0.0 ? polishedRoot
                                            : polishCluster(f, found[i].start, groupEnd,
                                                            options.parameterTolerance);
    result.roots.push_back(std::clamp(root, 0.0, 1.0));
    i = j + 1;
  }
  return result;
}

}  // namespace d2vdb::detail
