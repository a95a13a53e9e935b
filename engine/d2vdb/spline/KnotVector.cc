#include "d2vdb/spline/KnotVector.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb {
namespace {

void requireDegree(int degree) {
  if (degree < 1 || degree > kMaxSplineDegree) {
    throw InputError("knot vector: degree " + std::to_string(degree) +
                     " is not supported (expected 1 to " + std::to_string(kMaxSplineDegree) + ")");
  }
}

void requireDomain(ParameterInterval domain) {
  if (!std::isfinite(domain.start) || !std::isfinite(domain.end) || !(domain.start < domain.end)) {
    throw InputError("knot vector: domain [" + formatNumber(domain.start) + ", " +
                     formatNumber(domain.end) + "] is invalid (expected finite start < end)");
  }
}

void requireBasisFunctionCount(int degree, int count, const char* what) {
  if (count < degree + 1) {
    throw InputError(std::string("knot vector: ") + std::to_string(count) + " " + what +
                     " are too few for degree " + std::to_string(degree) + " (expected at least " +
                     std::to_string(degree + 1) + ")");
  }
}

// Knots t_i = domain.at((i - degree) / spanCount) for i = 0..count-1: equally spaced, with the
// domain ends hit exactly at i = degree and i = degree + spanCount.
std::vector<double> equallySpacedKnots(int degree, int count, int spanCount,
                                       ParameterInterval domain) {
  std::vector<double> knots(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    knots[static_cast<std::size_t>(i)] =
        domain.at(static_cast<double>(i - degree) / static_cast<double>(spanCount));
  }
  return knots;
}

}  // namespace

KnotVector::KnotVector(int degree, std::vector<double> knots)
    : degree_(degree), knots_(std::move(knots)), lastSpan_(0) {
  requireDegree(degree_);
  const int count = size();
  if (count < 2 * (degree_ + 1)) {
    throw InputError("knot vector has " + std::to_string(count) + " knots; degree " +
                     std::to_string(degree_) + " needs at least " +
                     std::to_string(2 * (degree_ + 1)) + " (2 * (degree + 1))");
  }
  for (int i = 0; i < count; ++i) {
    if (!std::isfinite((*this)[i])) {
      throw InputError("knot vector: knot " + std::to_string(i) + " is " +
                       formatNumber((*this)[i]) + " (expected a finite number)");
    }
    if (i > 0 && (*this)[i] < (*this)[i - 1]) {
      throw InputError("knot vector: knots must be non-decreasing, but knot " + std::to_string(i) +
                       " (" + formatNumber((*this)[i]) + ") is less than knot " +
                       std::to_string(i - 1) + " (" + formatNumber((*this)[i - 1]) + ")");
    }
  }
  const ParameterInterval dom = domain();
  if (!(dom.start < dom.end)) {
    throw InputError("knot vector: the domain [t_" + std::to_string(degree_) + ", t_" +
                     std::to_string(basisFunctionCount()) + "] = [" + formatNumber(dom.start) +
                     ", " + formatNumber(dom.end) + "] is empty");
  }
  for (int first = 0; first < count;) {
    int last = first;
    while (last + 1 < count && (*this)[last + 1] == (*this)[first]) ++last;
    const int multiplicity = last - first + 1;
    const double value = (*this)[first];
    const bool interior = value > dom.start && value < dom.end;
    const int allowed = interior ? degree_ : degree_ + 1;
    if (multiplicity > allowed) {
      throw InputError("knot vector: knot value " + formatNumber(value) + " occurs " +
                       std::to_string(multiplicity) + " times (knots " + std::to_string(first) +
                       " to " + std::to_string(last) + "); a degree-" + std::to_string(degree_) +
                       " knot vector allows " + std::to_string(allowed) +
                       (interior ? " inside the domain (more would make the spline discontinuous)"
                                 : " at or beyond the domain ends"));
    }
    first = last + 1;
  }
  lastSpan_ = basisFunctionCount() - 1;
  while ((*this)[lastSpan_] == dom.end) --lastSpan_;
}

KnotVector KnotVector::clamped(int degree, int controlPointCount, ParameterInterval domain) {
  requireDegree(degree);
  requireBasisFunctionCount(degree, controlPointCount, "control points");
  requireDomain(domain);
  const int spanCount = controlPointCount - degree;
  std::vector<double> knots =
      equallySpacedKnots(degree, controlPointCount + degree + 1, spanCount, domain);
  std::fill(knots.begin(), knots.begin() + degree, domain.start);
  std::fill(knots.end() - degree, knots.end(), domain.end);
  return KnotVector(degree, std::move(knots));
}

KnotVector KnotVector::uniform(int degree, int controlPointCount, ParameterInterval domain) {
  requireDegree(degree);
  requireBasisFunctionCount(degree, controlPointCount, "control points");
  requireDomain(domain);
  return KnotVector(degree, equallySpacedKnots(degree, controlPointCount + degree + 1,
                                               controlPointCount - degree, domain));
}

KnotVector KnotVector::periodic(int degree, int uniqueControlPointCount, ParameterInterval domain) {
  requireDegree(degree);
  requireBasisFunctionCount(degree, uniqueControlPointCount, "unique control points");
  requireDomain(domain);
  return KnotVector(degree, equallySpacedKnots(degree, uniqueControlPointCount + 2 * degree + 1,
                                               uniqueControlPointCount, domain));
}

int KnotVector::findSpan(double t) const {
  const ParameterInterval dom = domain();
  const double tolerance =
      16.0 * DBL_EPSILON * std::max({std::abs(dom.start), std::abs(dom.end), dom.length()});
  if (!(t >= dom.start - tolerance && t <= dom.end + tolerance)) {
    throw InputError("parameter " + formatNumber(t) + " is outside the domain [" +
                     formatNumber(dom.start) + ", " + formatNumber(dom.end) + "]");
  }
  if (t >= dom.end) return lastSpan_;
  // For t_p <= t < t_n the first knot greater than t lies in (p, n]; its predecessor starts the
  // span, which is non-empty because that knot is greater than t.
  const auto above =
      std::upper_bound(knots_.begin() + degree_ + 1, knots_.begin() + basisFunctionCount() + 1,
                       std::max(t, dom.start));
  return static_cast<int>(above - knots_.begin()) - 1;
}

int KnotVector::multiplicity(double t) const {
  const auto range = std::equal_range(knots_.begin(), knots_.end(), t);
  return static_cast<int>(range.second - range.first);
}

std::vector<double> KnotVector::breakpoints() const {
  std::vector<double> result;
  for (int i = degree_; i <= basisFunctionCount(); ++i) {
    if (result.empty() || (*this)[i] != result.back()) result.push_back((*this)[i]);
  }
  return result;
}

bool KnotVector::isUniformPeriodic() const {
  const int uniqueCount = basisFunctionCount() - degree_;
  if (uniqueCount < degree_ + 1) return false;
  const KnotVector expected = periodic(degree_, uniqueCount, domain());
  const double tolerance = 1e-9 * domain().length();
  for (int i = 0; i < size(); ++i) {
    if (!(std::abs((*this)[i] - expected[i]) <= tolerance)) return false;
  }
  return true;
}

}  // namespace d2vdb
