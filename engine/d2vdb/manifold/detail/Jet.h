// Internal: forward-mode derivatives in two variables (value, gradient and, for Order 2, the
// Hessian, for Order 3 the third derivatives), for composing the smooth maps of a pseudo-manifold
// with exact chain rules.
#pragma once

#include <Eigen/Core>

#include <cmath>

namespace d2vdb::detail {

/// Jet arithmetic is inlined into the evaluators (small functions called in tight sequences,
/// whose temporaries then stay in registers).
#define D2VDB_JET_INLINE inline __attribute__((always_inline))

/// Index conventions of the derivatives: the second derivative in directions (i, j) is h[i + j]
/// (xx, xy, yy), the third in (i, j, k) is t[i + j + k] (xxx, xxy, xyy, yyy). kTriple[m] is one
/// (i, j, k) of t[m].
inline constexpr int kTriple[4][3] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 1, 1}};

/// Storage of the third derivatives, zero-initialised: only jets of order 3 have it (an empty
/// base otherwise).
template <bool Present, typename T>
struct ThirdDerivatives {};
template <>
struct ThirdDerivatives<true, double> {
  double t[4] = {0.0, 0.0, 0.0, 0.0};
};
template <>
struct ThirdDerivatives<true, Eigen::Vector3d> {
  Eigen::Vector3d t[4] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                          Eigen::Vector3d::Zero()};
};

/// A scalar function of two variables at a point: value, gradient (d[0], d[1]) and, when
/// Order >= 2, the Hessian entries h (xx, xy, yy), when Order == 3 the third derivatives t
/// (xxx, xxy, xyy, yyy). Order 0 carries the value only.
template <int Order>
struct Jet : ThirdDerivatives<(Order >= 3), double> {
  double v = 0.0;
  double d[2] = {0.0, 0.0};
  double h[3] = {0.0, 0.0, 0.0};

  static Jet constant(double value) {
    Jet j;
    j.v = value;
    return j;
  }
  /// The independent variable `index` (0 or 1) at `value`.
  static Jet variable(double value, int index) {
    Jet j;
    j.v = value;
    if constexpr (Order >= 1) j.d[index] = 1.0;
    return j;
  }
  /// f(this) for a scalar function f with value f0 and derivatives f1, f2, f3 at v (chain
  /// rule; f3 is read only at Order 3).
  D2VDB_JET_INLINE Jet apply(double f0, double f1, double f2, double f3) const {
    Jet r;
    r.v = f0;
    if constexpr (Order >= 1) {
      r.d[0] = f1 * d[0];
      r.d[1] = f1 * d[1];
    }
    if constexpr (Order >= 2) {
      r.h[0] = f1 * h[0] + f2 * d[0] * d[0];
      r.h[1] = f1 * h[1] + f2 * d[0] * d[1];
      r.h[2] = f1 * h[2] + f2 * d[1] * d[1];
    }
    if constexpr (Order >= 3) {
      for (int m = 0; m < 4; ++m) {
        const int i = kTriple[m][0], j = kTriple[m][1], k = kTriple[m][2];
        r.t[m] = f1 * this->t[m] + f2 * (h[i + j] * d[k] + h[i + k] * d[j] + h[j + k] * d[i]) +
                 f3 * d[i] * d[j] * d[k];
      }
    }
    return r;
  }
};

template <int Order>
D2VDB_JET_INLINE Jet<Order> operator+(const Jet<Order>& a, const Jet<Order>& b) {
  Jet<Order> r;
  r.v = a.v + b.v;
  if constexpr (Order >= 1) {
    for (int i = 0; i < 2; ++i) r.d[i] = a.d[i] + b.d[i];
  }
  if constexpr (Order >= 2) {
    for (int i = 0; i < 3; ++i) r.h[i] = a.h[i] + b.h[i];
  }
  if constexpr (Order >= 3) {
    for (int i = 0; i < 4; ++i) r.t[i] = a.t[i] + b.t[i];
  }
  return r;
}

template <int Order>
D2VDB_JET_INLINE Jet<Order> operator-(const Jet<Order>& a, const Jet<Order>& b) {
  Jet<Order> r;
  r.v = a.v - b.v;
  if constexpr (Order >= 1) {
    for (int i = 0; i < 2; ++i) r.d[i] = a.d[i] - b.d[i];
  }
  if constexpr (Order >= 2) {
    for (int i = 0; i < 3; ++i) r.h[i] = a.h[i] - b.h[i];
  }
  if constexpr (Order >= 3) {
    for (int i = 0; i < 4; ++i) r.t[i] = a.t[i] - b.t[i];
  }
  return r;
}

template <int Order>
D2VDB_JET_INLINE Jet<Order> operator*(double s, const Jet<Order>& a) {
  Jet<Order> r;
  r.v = s * a.v;
  if constexpr (Order >= 1) {
    for (int i = 0; i < 2; ++i) r.d[i] = s * a.d[i];
  }
  if constexpr (Order >= 2) {
    for (int i = 0; i < 3; ++i) r.h[i] = s * a.h[i];
  }
  if constexpr (Order >= 3) {
    for (int i = 0; i < 4; ++i) r.t[i] = s * a.t[i];
  }
  return r;
}

template <int Order>
D2VDB_JET_INLINE Jet<Order> operator*(const Jet<Order>& a, const Jet<Order>& b) {
  Jet<Order> r;
  r.v = a.v * b.v;
  if constexpr (Order >= 1) {
    r.d[0] = a.d[0] * b.v + a.v * b.d[0];
    r.d[1] = a.d[1] * b.v + a.v * b.d[1];
  }
  if constexpr (Order >= 2) {
    r.h[0] = a.h[0] * b.v + 2.0 * a.d[0] * b.d[0] + a.v * b.h[0];
    r.h[1] = a.h[1] * b.v + a.d[0] * b.d[1] + a.d[1] * b.d[0] + a.v * b.h[1];
    r.h[2] = a.h[2] * b.v + 2.0 * a.d[1] * b.d[1] + a.v * b.h[2];
  }
  if constexpr (Order >= 3) {
    for (int m = 0; m < 4; ++m) {
      const int i = kTriple[m][0], j = kTriple[m][1], k = kTriple[m][2];
      r.t[m] = a.t[m] * b.v + a.v * b.t[m] + a.h[i + j] * b.d[k] + a.h[i + k] * b.d[j] +
               a.h[j + k] * b.d[i] + a.d[i] * b.h[j + k] + a.d[j] * b.h[i + k] +
               a.d[k] * b.h[i + j];
    }
  }
  return r;
}

template <int Order>
D2VDB_JET_INLINE Jet<Order> sqrt(const Jet<Order>& a) {
  const double s = std::sqrt(a.v);
  return a.apply(s, 0.5 / s, -0.25 / (s * a.v), 0.375 / (s * a.v * a.v));
}

/// sin(a) and cos(a) when their values at a are already known (no trigonometry).
template <int Order>
D2VDB_JET_INLINE void sinCosKnown(const Jet<Order>& a, double s, double c, Jet<Order>& sine,
                                  Jet<Order>& cosine) {
  sine = a.apply(s, c, -s, -c);
  cosine = a.apply(c, -s, -c, s);
}

/// sin(a) and cos(a) together (one evaluation of each at the value).
template <int Order>
D2VDB_JET_INLINE void sinCos(const Jet<Order>& a, Jet<Order>& sine, Jet<Order>& cosine) {
  sinCosKnown(a, std::sin(a.v), std::cos(a.v), sine, cosine);
}

/// The third derivative t[m] of F(x(s), y(s)) for a function F of two variables with partial
/// derivatives Fx ... Fyyy at (x.v, y.v) and order-3 jets x, y (chain rule of Faa di Bruno). T is
/// double or a vector type.
template <typename T, typename J>
D2VDB_JET_INLINE T chainThird(int m, const T& fx, const T& fy, const T& fxx, const T& fxy,
                              const T& fyy, const T& fxxx, const T& fxxy, const T& fxyy,
                              const T& fyyy, const J& x, const J& y) {
  const int i = kTriple[m][0], j = kTriple[m][1], k = kTriple[m][2];
  // Products of one second and one first derivative over the three ways to split (i, j, k).
  const double xx = x.h[i + j] * x.d[k] + x.h[i + k] * x.d[j] + x.h[j + k] * x.d[i];
  const double xy = x.h[i + j] * y.d[k] + x.h[i + k] * y.d[j] + x.h[j + k] * y.d[i] +
                    y.h[i + j] * x.d[k] + y.h[i + k] * x.d[j] + y.h[j + k] * x.d[i];
  const double yy = y.h[i + j] * y.d[k] + y.h[i + k] * y.d[j] + y.h[j + k] * y.d[i];
  const double xxx = x.d[i] * x.d[j] * x.d[k];
  const double xxy = x.d[i] * x.d[j] * y.d[k] + x.d[i] * y.d[j] * x.d[k] + y.d[i] * x.d[j] * x.d[k];
  const double xyy = x.d[i] * y.d[j] * y.d[k] + y.d[i] * x.d[j] * y.d[k] + y.d[i] * y.d[j] * x.d[k];
  const double yyy = y.d[i] * y.d[j] * y.d[k];
  return fx * x.t[m] + fy * y.t[m] + fxx * xx + fxy * xy + fyy * yy + fxxx * xxx + fxxy * xxy +
         fxyy * xyy + fyyy * yyy;
}

/// The polar angle of (x, y) with the given value (any branch) and the angle's derivatives:
/// d angle = (x dy - y dx) / r^2 (the same on every branch).
template <int Order>
D2VDB_JET_INLINE Jet<Order> polarAngle(const Jet<Order>& y, const Jet<Order>& x, double value) {
  Jet<Order> r;
  r.v = value;
  if constexpr (Order >= 1) {
    const double rr = x.v * x.v + y.v * y.v;
    // grad angle with respect to (x, y): (-y, x) / rr; second derivatives:
    // a_xx = 2 x y / rr^2, a_xy = (y^2 - x^2) / rr^2, a_yy = -2 x y / rr^2.
    const double ax = -y.v / rr;
    const double ay = x.v / rr;
    for (int i = 0; i < 2; ++i) r.d[i] = ax * x.d[i] + ay * y.d[i];
    if constexpr (Order >= 2) {
      const double rr2 = rr * rr;
      const double axx = 2.0 * x.v * y.v / rr2;
      const double axy = (y.v * y.v - x.v * x.v) / rr2;
      const double ayy = -axx;
      const int pairs[3][2] = {{0, 0}, {0, 1}, {1, 1}};
      for (int k = 0; k < 3; ++k) {
        const int i = pairs[k][0];
        const int j = pairs[k][1];
        r.h[k] = ax * x.h[k] + ay * y.h[k] + axx * x.d[i] * x.d[j] +
                 axy * (x.d[i] * y.d[j] + y.d[i] * x.d[j]) + ayy * y.d[i] * y.d[j];
      }
      if constexpr (Order >= 3) {
        // The angle is harmonic: a_xxx = 2 y (y^2 - 3 x^2) / rr^3 = -a_xyy,
        // a_xxy = 2 x (x^2 - 3 y^2) / rr^3 = -a_yyy.
        const double rr3 = rr2 * rr;
        const double axxx = 2.0 * y.v * (y.v * y.v - 3.0 * x.v * x.v) / rr3;
        const double axxy = 2.0 * x.v * (x.v * x.v - 3.0 * y.v * y.v) / rr3;
        for (int m = 0; m < 4; ++m) {
          r.t[m] = chainThird(m, ax, ay, axx, axy, ayy, axxx, axxy, -axxx, -axxy, x, y);
        }
      }
    }
  }
  return r;
}

/// atan2(y, x) with the derivatives of the polar angle. The value is the principal one, in
/// (-pi, pi].
template <int Order>
Jet<Order> atan2(const Jet<Order>& y, const Jet<Order>& x) {
  return polarAngle(y, x, std::atan2(y.v, x.v));
}

/// A point of R^3 as a function of two variables: value, first, (Order >= 2) second and
/// (Order 3) third derivatives, indexed as in Jet.
template <int Order>
struct Jet3 : ThirdDerivatives<(Order >= 3), Eigen::Vector3d> {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d d[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  Eigen::Vector3d h[3] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                          Eigen::Vector3d::Zero()};
};

/// Adds w * f (scalar jet times point jet) to `sum`.
template <int Order>
D2VDB_JET_INLINE void addProduct(Jet3<Order>& sum, const Jet<Order>& w, const Jet3<Order>& f) {
  sum.v += w.v * f.v;
  if constexpr (Order >= 1) {
    for (int i = 0; i < 2; ++i) sum.d[i] += w.d[i] * f.v + w.v * f.d[i];
  }
  if constexpr (Order >= 2) {
    sum.h[0] += w.h[0] * f.v + 2.0 * w.d[0] * f.d[0] + w.v * f.h[0];
    sum.h[1] += w.h[1] * f.v + w.d[0] * f.d[1] + w.d[1] * f.d[0] + w.v * f.h[1];
    sum.h[2] += w.h[2] * f.v + 2.0 * w.d[1] * f.d[1] + w.v * f.h[2];
  }
  if constexpr (Order >= 3) {
    for (int m = 0; m < 4; ++m) {
      const int i = kTriple[m][0], j = kTriple[m][1], k = kTriple[m][2];
      sum.t[m] += w.t[m] * f.v + w.v * f.t[m] + w.h[i + j] * f.d[k] + w.h[i + k] * f.d[j] +
                  w.h[j + k] * f.d[i] + w.d[i] * f.h[j + k] + w.d[j] * f.h[i + k] +
                  w.d[k] * f.h[i + j];
    }
  }
}

/// The quotient n / den of a point jet by a scalar jet (den.v != 0).
template <int Order>
D2VDB_JET_INLINE Jet3<Order> divide(const Jet3<Order>& n, const Jet<Order>& den) {
  Jet3<Order> q;
  const double inv = 1.0 / den.v;
  q.v = n.v * inv;
  if constexpr (Order >= 1) {
    for (int i = 0; i < 2; ++i) q.d[i] = (n.d[i] - den.d[i] * q.v) * inv;
  }
  if constexpr (Order >= 2) {
    // q den = n  =>  q_ab den + q_a den_b + q_b den_a + q den_ab = n_ab.
    q.h[0] = (n.h[0] - 2.0 * q.d[0] * den.d[0] - q.v * den.h[0]) * inv;
    q.h[1] = (n.h[1] - q.d[0] * den.d[1] - q.d[1] * den.d[0] - q.v * den.h[1]) * inv;
    q.h[2] = (n.h[2] - 2.0 * q.d[1] * den.d[1] - q.v * den.h[2]) * inv;
  }
  if constexpr (Order >= 3) {
    // Differentiating once more: q_abc den + (q_ab den_c + q_ac den_b + q_bc den_a)
    //   + (q_a den_bc + q_b den_ac + q_c den_ab) + q den_abc = n_abc.
    for (int m = 0; m < 4; ++m) {
      const int i = kTriple[m][0], j = kTriple[m][1], k = kTriple[m][2];
      q.t[m] =
          (n.t[m] - q.h[i + j] * den.d[k] - q.h[i + k] * den.d[j] - q.h[j + k] * den.d[i] -
           q.d[i] * den.h[j + k] - q.d[j] * den.h[i + k] - q.d[k] * den.h[i + j] - q.v * den.t[m]) *
          inv;
    }
  }
  return q;
}

#undef D2VDB_JET_INLINE

}  // namespace d2vdb::detail
