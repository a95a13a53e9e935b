#include "d2vdb/support/SphericalHarmonics.h"

#include <cmath>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/support/detail/HarmonicKernels.h"

// The recurrences and ladder relations below follow from the generating function of the harmonic
// polynomials, w^l / l! with w = z + (i/2)((x - i y) u + (x + i y) / u): the coefficient of u^-m
// is (i/2)^m G_l^m with G_l^m = (x + i y)^m Q_l^m(x^2 + y^2, z) (m >= 0, Q real), and since
// (i cos a, i sin a, 1) is an isotropic vector every w^l is harmonic. Differentiating w gives
//   d/dz G_l^m = G_{l-1}^m,  (d/dx + i d/dy) G_l^m = -G_{l-1}^{m+1} / 2,
//   (d/dx - i d/dy) G_l^m = 2 G_{l-1}^{m-1}  (m >= 1; for m = 0 it is -conj(G_{l-1}^1) / 2),
// and the G_l^m satisfy (l - m)(l + m) G_l^m = (2l - 1) z G_{l-1}^m - r^2 G_{l-2}^m, the Legendre
// recurrence, with G_l^m = 2^m r^l P_l^m(cos theta) e^{i m phi} / (l + m)!. The orthonormal real
// harmonics are N_lm Re G_l^m and N_lm Im G_l^m with
//   N_lm^2 = (2l + 1) (l - m)! (l + m)! sigma_m / (4 pi 4^m),  sigma_0 = 1, sigma_m = 2 (m > 0).
// (See e.g. E. W. Hobson, The Theory of Spherical and Ellipsoidal Harmonics, 1931, ch. III, for
// the classical ladder operators of solid harmonics.)

namespace d2vdb {
namespace detail {
namespace {

void checkDegree(int degree) {
  if (degree < 0 || degree > kMaxSupportDegree) {
    throw InputError("spherical-harmonic degree " + std::to_string(degree) +
                     " is not supported (expected 0 to " + std::to_string(kMaxSupportDegree) + ")");
  }
}

// sigma_m of the normalisation (2 for the cosine/sine pairs, 1 for m = 0).
double sigma(int m) {
  return m > 0 ? 2.0 : 1.0;
}

// N_lm / N_{l-1,m+1}, N_lm / N_{l-1,m-1} and N_lm / N_{l-1,m} (see the file comment).
double ratioUp(int l, int m) {
  const double dl = l;
  const double dm = m;
  return std::sqrt((2.0 * dl + 1.0) / (2.0 * dl - 1.0) * (dl - dm) * (dl - dm - 1.0) * 4.0 *
                   sigma(m) / sigma(m + 1));
}
double ratioDown(int l, int m) {
  const double dl = l;
  const double dm = m;
  return std::sqrt((2.0 * dl + 1.0) / (2.0 * dl - 1.0) * (dl + dm) * (dl + dm - 1.0) / 4.0 *
                   sigma(m) / sigma(m - 1));
}
double ratioSame(int l, int m) {
  const double dl = l;
  const double dm = m;
  return std::sqrt((2.0 * dl + 1.0) / (2.0 * dl - 1.0) * (dl - dm) * (dl + dm));
}

}  // namespace

RecurrenceTables::RecurrenceTables() {
  const int maxDegree = kMaxSupportDegree;
  sectoral.assign(maxDegree + 1, 0.0);
  sectoral[0] = 1.0 / std::sqrt(4.0 * kPi);
  for (int m = 1; m <= maxDegree; ++m) {
    const double dm = m;
    sectoral[m] = sectoral[m - 1] * std::sqrt((2.0 * dm + 1.0) / (2.0 * dm)) *
                  (m == 1 ? std::sqrt(2.0) : 1.0);
  }
  a.assign(maxDegree + 1, std::vector<double>(maxDegree + 1, 0.0));
  b = a;
  for (int l = 1; l <= maxDegree; ++l) {
    for (int m = 0; m < l; ++m) {
      const double dl = l;
      const double dm = m;
      const double lm = dl * dl - dm * dm;
      a[l][m] = std::sqrt((4.0 * dl * dl - 1.0) / lm);
      b[l][m] = l >= 2 ? std::sqrt((2.0 * dl + 1.0) * (dl - 1.0 - dm) * (dl - 1.0 + dm) /
                                   ((2.0 * dl - 3.0) * lm))
                       : 0.0;
    }
  }
}

const RecurrenceTables& recurrenceTables() {
  static const RecurrenceTables tables;
  return tables;
}

int harmonicDegreeOf(int index) {
  int l = static_cast<int>(std::sqrt(static_cast<double>(index)));
  while (l * l > index) --l;
  while ((l + 1) * (l + 1) <= index) ++l;
  return l;
}

void evaluateHarmonicBlock(int degree, int count, const double* x, const double* y, const double* z,
                           double* out, int stride) {
  if (count <= 0) return;
  const RecurrenceTables& tables = recurrenceTables();
  using ConstArray = Eigen::Map<const Eigen::ArrayXd>;
  const ConstArray X(x, count);
  const ConstArray Y(y, count);
  const ConstArray Z(z, count);
  const auto column = [&](int index) {
    return Eigen::Map<Eigen::ArrayXd>(out + static_cast<std::ptrdiff_t>(index) * stride, count);
  };
  Eigen::ArrayXd re = Eigen::ArrayXd::Ones(count);
  Eigen::ArrayXd im = Eigen::ArrayXd::Zero(count);
  Eigen::ArrayXd lambda2(count);  // Lambda_{l-2}^m
  Eigen::ArrayXd lambda1(count);  // Lambda_{l-1}^m
  Eigen::ArrayXd lambda(count);   // Lambda_l^m
  Eigen::ArrayXd scratch(count);
  for (int m = 0; m <= degree; ++m) {
    if (m > 0) {
      scratch = re * X - im * Y;
      im = re * Y + im * X;
      re = scratch;
    }
    const double kappa = tables.sectoral[static_cast<std::size_t>(m)];
    const auto store = [&](int l, const Eigen::ArrayXd& values) {
      if (m == 0) {
        column(harmonicIndex(l, 0)) = values;
      } else {
        column(harmonicIndex(l, m)) = values * re;
        column(harmonicIndex(l, -m)) = values * im;
      }
    };
    lambda1.setConstant(kappa);
    store(m, lambda1);
    if (m + 1 > degree) continue;
    lambda = tables.a[static_cast<std::size_t>(m + 1)][static_cast<std::size_t>(m)] * kappa * Z;
    store(m + 1, lambda);
    for (int l = m + 2; l <= degree; ++l) {
      lambda2.swap(lambda1);
      lambda1.swap(lambda);
      const double al = tables.a[static_cast<std::size_t>(l)][static_cast<std::size_t>(m)];
      const double bl = tables.b[static_cast<std::size_t>(l)][static_cast<std::size_t>(m)];
      lambda = al * Z * lambda1 - bl * lambda2;
      store(l, lambda);
    }
  }
}

Eigen::SparseMatrix<double> partialDerivativeMatrix(int degree, int axis) {
  checkDegree(degree);
  if (axis < 0 || axis > 2) throw InputError("partial derivative axis must be 0, 1 or 2");
  const int rows = harmonicCount(degree - 1);
  const int cols = harmonicCount(degree);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(2 * cols));
  // Output harmonic (l - 1, m') of cosine (C) or sine (S) type, if it exists.
  const auto addC = [&](int l, int mOut, int in, double value) {
    if (mOut >= 0 && mOut <= l - 1) entries.emplace_back(harmonicIndex(l - 1, mOut), in, value);
  };
  const auto addS = [&](int l, int mOut, int in, double value) {
    if (mOut >= 1 && mOut <= l - 1) entries.emplace_back(harmonicIndex(l - 1, -mOut), in, value);
  };
  for (int l = 1; l <= degree; ++l) {
    for (int m = 0; m <= l; ++m) {
      const int inC = harmonicIndex(l, m);
      const int inS = harmonicIndex(l, -m);
      const double up = m + 1 <= l - 1 ? ratioUp(l, m) : 0.0;
      const double down = m >= 1 ? ratioDown(l, m) : 0.0;
      switch (axis) {
        case 0:  // d/dx
          if (m == 0) {
            addC(l, 1, inC, -0.5 * up);
          } else {
            addC(l, m + 1, inC, -0.25 * up);
            addC(l, m - 1, inC, down);
            addS(l, m + 1, inS, -0.25 * up);
            addS(l, m - 1, inS, down);
          }
          break;
        case 1:  // d/dy
          if (m == 0) {
            addS(l, 1, inC, -0.5 * up);
          } else {
            addS(l, m + 1, inC, -0.25 * up);
            addS(l, m - 1, inC, -down);
            addC(l, m + 1, inS, 0.25 * up);
            addC(l, m - 1, inS, down);
          }
          break;
        default:  // d/dz
          if (m <= l - 1) {
            const double same = ratioSame(l, m);
            addC(l, m, inC, same);
            if (m >= 1) addS(l, m, inS, same);
          }
          break;
      }
    }
  }
  Eigen::SparseMatrix<double> matrix(rows, cols);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

}  // namespace detail

Eigen::VectorXd evaluateHarmonics(int degree, const Eigen::Vector3d& unitNormal) {
  detail::checkDegree(degree);
  Eigen::VectorXd values(harmonicCount(degree));
  detail::evaluateHarmonicBlock(degree, 1, &unitNormal.x(), &unitNormal.y(), &unitNormal.z(),
                                values.data(), 1);
  return values;
}

Eigen::VectorXd harmonicPartialDerivative(const Eigen::VectorXd& coefficients, int degree,
                                          int axis) {
  detail::checkDegree(degree);
  if (coefficients.size() != harmonicCount(degree)) {
    throw InputError("a degree-" + std::to_string(degree) + " coefficient vector needs " +
                     std::to_string(harmonicCount(degree)) + " entries, got " +
                     std::to_string(coefficients.size()));
  }
  return detail::partialDerivativeMatrix(degree, axis) * coefficients;
}

}  // namespace d2vdb
