#include "d2vdb/spline/Bernstein.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/spline/detail/BernsteinAlgorithms.h"

namespace d2vdb {
namespace {

using Controls = detail::BernsteinControls<1>;

void requireBernsteinDegree(int degree, const char* what) {
  if (degree < 0 || degree > kMaxBernsteinDegree) {
    throw InputError(std::string(what) + ": degree " + std::to_string(degree) +
                     " is not supported (expected 0 to " + std::to_string(kMaxBernsteinDegree) +
                     ")");
  }
}

void requireValidCoefficients(const double* values, std::size_t count) {
  if (count == 0 || count > static_cast<std::size_t>(kMaxBernsteinDegree + 1)) {
    throw InputError("Bernstein polynomial: " + std::to_string(count) +
                     " coefficients given (expected 1 to " +
                     std::to_string(kMaxBernsteinDegree + 1) + ")");
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(values[i])) {
      throw InputError("Bernstein polynomial: coefficient " + std::to_string(i) + " is " +
                       formatNumber(values[i]) + " (expected a finite number)");
    }
  }
}

Controls toControls(const double* values, std::size_t count) {
  requireValidCoefficients(values, count);
  Controls controls(1, static_cast<Eigen::Index>(count));
  for (std::size_t i = 0; i < count; ++i) controls[static_cast<Eigen::Index>(i)] = values[i];
  return controls;
}

}  // namespace

double bernsteinBasis(int degree, int index, double t) {
  requireBernsteinDegree(degree, "Bernstein basis");
  if (index < 0 || index > degree) {
    throw InputError("Bernstein basis: index " + std::to_string(index) +
                     " is out of range for degree " + std::to_string(degree) + " (expected 0 to " +
                     std::to_string(degree) + ")");
  }
  return detail::kBinomials.value[degree][index] * std::pow(t, index) *
         std::pow(1.0 - t, degree - index);
}

BernsteinBasisValues bernsteinBasisValues(int degree, double t) {
  requireBernsteinDegree(degree, "Bernstein basis");
  BernsteinBasisValues values(degree + 1);
  values[0] = 1.0;
  // In place from the top: B_{i,d+1} = (1 - t) B_{i,d} + t B_{i-1,d}.
  for (int d = 0; d < degree; ++d) {
    values[d + 1] = t * values[d];
    for (int i = d; i >= 1; --i) values[i] = (1.0 - t) * values[i] + t * values[i - 1];
    values[0] = (1.0 - t) * values[0];
  }
  return values;
}

BernsteinPolynomial::BernsteinPolynomial(const Coefficients& coefficients)
    : coefficients_(
          toControls(coefficients.data(), static_cast<std::size_t>(coefficients.cols()))) {}

BernsteinPolynomial::BernsteinPolynomial(std::initializer_list<double> coefficients)
    : coefficients_(toControls(coefficients.begin(), coefficients.size())) {}

BernsteinPolynomial::BernsteinPolynomial(const std::vector<double>& coefficients)
    : coefficients_(toControls(coefficients.data(), coefficients.size())) {}

BernsteinPolynomial BernsteinPolynomial::constant(double value, int degree) {
  requireBernsteinDegree(degree, "Bernstein polynomial");
  if (!std::isfinite(value)) {
    throw InputError("Bernstein polynomial: constant " + formatNumber(value) + " is not finite");
  }
  return BernsteinPolynomial(Unchecked{}, Coefficients::Constant(1, degree + 1, value));
}

double BernsteinPolynomial::evaluate(double t) const {
  return detail::deCasteljauEvaluate<1>(coefficients_, t)[0];
}

std::pair<BernsteinPolynomial, BernsteinPolynomial> BernsteinPolynomial::subdivide(double t) const {
  Coefficients left;
  Coefficients right;
  detail::deCasteljauSplit<1>(coefficients_, t, left, right);
  return {BernsteinPolynomial(Unchecked{}, left), BernsteinPolynomial(Unchecked{}, right)};
}

BernsteinPolynomial BernsteinPolynomial::restricted(double a, double b) const {
  if (!std::isfinite(a) || !std::isfinite(b) || a == b) {
    throw InputError("Bernstein polynomial: cannot restrict to [" + formatNumber(a) + ", " +
                     formatNumber(b) + "] (expected finite a != b)");
  }
  return BernsteinPolynomial(Unchecked{}, detail::restrictTo<1>(coefficients_, a, b));
}

BernsteinPolynomial BernsteinPolynomial::derivative() const {
  return BernsteinPolynomial(Unchecked{}, detail::differentiate<1>(coefficients_));
}

BernsteinPolynomial BernsteinPolynomial::elevated(int times) const {
  if (times < 0 || degree() + times > kMaxBernsteinDegree) {
    throw InputError("Bernstein polynomial: cannot elevate degree " + std::to_string(degree()) +
                     " by " + std::to_string(times) + " (the result must be at most degree " +
                     std::to_string(kMaxBernsteinDegree) + ")");
  }
  Coefficients result = coefficients_;
  for (int i = 0; i < times; ++i) result = detail::elevateOnce<1>(result);
  return BernsteinPolynomial(Unchecked{}, result);
}

BernsteinPolynomial operator*(const BernsteinPolynomial& f, const BernsteinPolynomial& g) {
  if (f.degree() + g.degree() > kMaxBernsteinDegree) {
    throw InputError("Bernstein polynomial: the product of degrees " + std::to_string(f.degree()) +
                     " and " + std::to_string(g.degree()) + " exceeds degree " +
                     std::to_string(kMaxBernsteinDegree));
  }
  return BernsteinPolynomial(BernsteinPolynomial::Unchecked{},
                             detail::productCoefficients<1>(f.coefficients_, g.coefficients_));
}

BernsteinPolynomial operator+(const BernsteinPolynomial& f, const BernsteinPolynomial& g) {
  const int degree = std::max(f.degree(), g.degree());
  return BernsteinPolynomial(BernsteinPolynomial::Unchecked{},
                             f.elevated(degree - f.degree()).coefficients_ +
                                 g.elevated(degree - g.degree()).coefficients_);
}

BernsteinPolynomial operator-(const BernsteinPolynomial& f, const BernsteinPolynomial& g) {
  return f + (-1.0) * g;
}

BernsteinPolynomial operator*(double s, const BernsteinPolynomial& f) {
  return BernsteinPolynomial(BernsteinPolynomial::Unchecked{}, s * f.coefficients_);
}

}  // namespace d2vdb
