#include "d2vdb/measure/detail/SquaredDistanceTensor.h"

#include <array>
#include <limits>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {
namespace {

// Binomial coefficient C(n, k) for n <= 2 kMaxSplineDegree, exact in double.
double binomial(int n, int k) {
  double value = 1.0;
  for (int i = 1; i <= k; ++i) value = value * (n - k + i) / i;
  return value;
}

// Product weights w_{i, j} = C(n, i) C(n, j) / C(2n, i + j) of the Bernstein product rule
// B_{i,n} B_{j,n} = w_{i,j} B_{i+j,2n}.
using WeightTable = std::array<std::array<double, kMaxSplineDegree + 1>, kMaxSplineDegree + 1>;

// The weight tables of every degree 0..kMaxSplineDegree, built once.
const WeightTable& productWeights(int n) {
  static const std::array<WeightTable, kMaxSplineDegree + 1> tables = [] {
    std::array<WeightTable, kMaxSplineDegree + 1> all{};
    for (int degree = 0; degree <= kMaxSplineDegree; ++degree) {
      for (int i = 0; i <= degree; ++i) {
        for (int j = 0; j <= degree; ++j) {
          all[degree][i][j] =
              binomial(degree, i) * binomial(degree, j) / binomial(2 * degree, i + j);
        }
      }
    }
    return all;
  }();
  return tables[n];
}

}  // namespace

SquaredDistanceTensor::SquaredDistanceTensor(const BezierCurve& p, const BezierCurve& q) {
  const int n = p.degree();
  const int m = q.degree();
  if (n > kMaxSplineDegree || m > kMaxSplineDegree) {
    throw InputError("squared distance tensor: curve degrees " + std::to_string(n) + " and " +
                     std::to_string(m) + " exceed the maximum " + std::to_string(kMaxSplineDegree));
  }
  const WeightTable& weightsU = productWeights(n);
  const WeightTable& weightsV = productWeights(m);
  // Differences D_{i, j} = P_i - Q_j: S = sum w_u w_v D_{i,j} . D_{i',j'} over i + i' = r,
  // j + j' = k.
  std::array<std::array<Eigen::Vector3d, kMaxSplineDegree + 1>, kMaxSplineDegree + 1> difference;
  double largest = 0.0;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= m; ++j) {
      difference[i][j] = p.controlPoint(i) - q.controlPoint(j);
      largest = std::max(largest, difference[i][j].squaredNorm());
    }
  }
  coefficients_ = Coefficients::Zero(2 * n + 1, 2 * m + 1);
  for (int i = 0; i <= n; ++i) {
    for (int i2 = 0; i2 <= n; ++i2) {
      const double weightU = weightsU[i][i2];
      for (int j = 0; j <= m; ++j) {
        for (int j2 = 0; j2 <= m; ++j2) {
          coefficients_(i + i2, j + j2) +=
              weightU * weightsV[j][j2] * difference[i][j].dot(difference[i2][j2]);
        }
      }
    }
  }
  roundingBound_ = 16.0 * (n + m + 2) * std::numeric_limits<double>::epsilon() * largest;
}

double SquaredDistanceTensor::evaluate(double u, double v) const {
  const BernsteinBasisValues basisU = bernsteinBasisValues(degreeU(), u);
  const BernsteinBasisValues basisV = bernsteinBasisValues(degreeV(), v);
  return basisU.dot(coefficients_ * basisV);
}

}  // namespace d2vdb::detail
