#include "d2vdb/spline/BasisFunctions.h"

#include <array>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

void requireSpan(const KnotVector& knots, int span) {
  if (span < knots.degree() || span >= knots.basisFunctionCount() ||
      !(knots[span] < knots[span + 1])) {
    throw InputError("basis functions: " + std::to_string(span) +
                     " is not a non-empty knot span (expected an index from findSpan, between " +
                     std::to_string(knots.degree()) + " and " +
                     std::to_string(knots.basisFunctionCount() - 1) + ")");
  }
}

// Raises the nonzero basis values on `span` from degree d to d + 1 in place: on entry values[j]
// holds N_{span-d+j,d}(t) for j = 0..d, on return N_{span-d-1+j,d+1}(t) for j = 0..d+1, by
//   N_{i,d+1} = (t - t_i) / (t_{i+d+1} - t_i) N_{i,d} + (t_{i+d+2} - t) / (t_{i+d+2} - t_{i+1})
//   N_{i+1,d}.
// Functions indexed outside span-d..span vanish on the span; those inside have supports that
// contain the non-empty span, so every denominator used is positive.
template <typename Array>
void raiseDegree(const double* knot, int span, int d, double t, Array& values) {
  values[d + 1] = 0.0;
  for (int j = d + 1; j >= 0; --j) {
    const int i = span - d - 1 + j;
    double value = 0.0;
    if (j >= 1) value += (t - knot[i]) / (knot[i + d + 1] - knot[i]) * values[j - 1];
    if (j <= d) value += (knot[i + d + 2] - t) / (knot[i + d + 2] - knot[i + 1]) * values[j];
    values[j] = value;
  }
}

// Same index bookkeeping for derivatives: on entry values[j] = D^r N_{span-d+j,d}, on return
// D^{r+1} N_{span-d-1+j,d+1}, by
//   D N_{i,d+1} = (d + 1) (N_{i,d} / (t_{i+d+1} - t_i) - N_{i+1,d} / (t_{i+d+2} - t_{i+1})).
template <typename Array>
void raiseDegreeDifferentiating(const double* knot, int span, int d, Array& values) {
  values[d + 1] = 0.0;
  const double factor = d + 1;
  for (int j = d + 1; j >= 0; --j) {
    const int i = span - d - 1 + j;
    double value = 0.0;
    if (j >= 1) value += values[j - 1] / (knot[i + d + 1] - knot[i]);
    if (j <= d) value -= values[j] / (knot[i + d + 2] - knot[i + 1]);
    values[j] = factor * value;
  }
}

}  // namespace

BasisValues basisValues(const KnotVector& knots, int span, double t) {
  requireSpan(knots, span);
  const int p = knots.degree();
  const double* knot = knots.values().data();
  BasisValues values(p + 1);
  values[0] = 1.0;
  for (int d = 0; d < p; ++d) raiseDegree(knot, span, d, t, values);
  return values;
}

BasisDerivatives basisDerivatives(const KnotVector& knots, int span, double t, int maxOrder) {
  requireSpan(knots, span);
  if (maxOrder < 0 || maxOrder > kMaxSplineDegree) {
    throw InputError("basis functions: derivative order " + std::to_string(maxOrder) +
                     " is not supported (expected 0 to " + std::to_string(kMaxSplineDegree) + ")");
  }
  const int p = knots.degree();
  const double* knot = knots.values().data();

  // lowerDegree[d][j] = N_{span-d+j,d}(t) for every degree d = 0..p (the Cox-de Boor triangle).
  std::array<std::array<double, kMaxSplineDegree + 1>, kMaxSplineDegree + 1> lowerDegree;
  lowerDegree[0][0] = 1.0;
  for (int d = 0; d < p; ++d) {
    for (int j = 0; j <= d; ++j) lowerDegree[d + 1][j] = lowerDegree[d][j];
    raiseDegree(knot, span, d, t, lowerDegree[d + 1]);
  }

  BasisDerivatives result = BasisDerivatives::Zero(maxOrder + 1, p + 1);
  for (int j = 0; j <= p; ++j) result(0, j) = lowerDegree[p][j];
  // D^k N_{.,p} from the degree p - k values, differentiated while raising the degree k times.
  for (int k = 1; k <= maxOrder && k <= p; ++k) {
    std::array<double, kMaxSplineDegree + 1> values;
    for (int j = 0; j <= p - k; ++j) values[j] = lowerDegree[p - k][j];
    for (int d = p - k; d < p; ++d) raiseDegreeDifferentiating(knot, span, d, values);
    for (int j = 0; j <= p; ++j) result(k, j) = values[j];
  }
  return result;
}

}  // namespace d2vdb
