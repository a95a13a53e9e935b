// The pseudo-manifold's construction (charts fitted per vertex), its evaluation with derivatives,
// and the projection of points onto it (ProjectionRun).
#include "d2vdb/manifold/PseudoManifold.h"

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/BumpFunction.h"
#include "d2vdb/manifold/detail/ChartMath.h"
#include "d2vdb/manifold/detail/Jet.h"
#include "d2vdb/spline/Bernstein.h"

namespace d2vdb {

using detail::Jet;
using detail::Jet3;
using detail::kCos30;
using detail::PolarMap;
using Index = HalfEdgeMesh::Index;

namespace {

constexpr int kMaxBidegree = 12;

/// Two doubles in one SIMD register (GCC/Clang vector extension; plain SSE2 on x86-64). May
/// alias double and needs only a double's alignment, so rows of a double array can be read as
/// pairs.
typedef double Pair __attribute__((vector_size(16), aligned(8), may_alias));

/// Number of Pairs per row of a bidegree-d patch: d + 1 values padded to an even count.
constexpr int pairsPerRow(int d) {
  return (d + 2) / 2;
}

/// The binomial coefficients C(N, i), i = 0..N, zero-padded to 2 pairsPerRow(D) entries.
template <int D, int N>
struct PairBinomials {
  static constexpr std::array<double, 2 * pairsPerRow(D)> values = [] {
    std::array<std::array<double, D + 1>, D + 1> c{};
    for (int n = 0; n <= D; ++n) {
      c[n][0] = c[n][n] = 1.0;
      for (int k = 1; k < n; ++k) c[n][k] = c[n - 1][k - 1] + c[n - 1][k];
    }
    std::array<double, 2 * pairsPerRow(D)> out{};
    for (int i = 0; i <= N; ++i) out[i] = c[N][i];
    return out;
  }();
};

/// The Bernstein basis of degree N <= D at s, B^N_i = C(N, i) s^i (1 - s)^(N - i), as pairs
/// (B_2k, B_2k+1), zero beyond N. powers[k] = (s^2k, s^2k+1); r = 1 - s, r2 = r^2. Independent
/// products in registers: no long recurrence, no scalar stores read back as pairs.
template <int D, int N>
inline void pairBasis(const Pair* powers, double r, double r2, Pair* out) {
  constexpr int count = pairsPerRow(D);
  constexpr int top = N / 2;  // the pair holding B_N
  constexpr auto& binomials = PairBinomials<D, N>::values;
  for (int k = count - 1; k > top; --k) out[k] = Pair{0.0, 0.0};
  // (r^(N - 2k), r^(N - 2k - 1)), with r^-1 read as 0.
  Pair rPowers = (N % 2 == 0) ? Pair{1.0, 0.0} : Pair{r, 1.0};
  for (int k = top; k >= 0; --k) {
    out[k] = Pair{binomials[2 * k], binomials[2 * k + 1]} * powers[k] * rPowers;
    rPowers = (N % 2 == 0 && k == top) ? Pair{r2, r} : rPowers * r2;
  }
}

/// The Bernstein basis of fixed degree D at s with first (Order >= 1), second (Order >= 2) and
/// third (Order 3) derivatives, as pairs (see pairBasis): dB^D_i = D (B^(D-1)_(i-1) - B^(D-1)_i),
/// d2B^D_i = D (D - 1) (B^(D-2)_(i-2) - 2 B^(D-2)_(i-1) + B^(D-2)_i),
/// d3B^D_i = D (D - 1) (D - 2) (B^(D-3)_(i-3) - 3 B^(D-3)_(i-2) + 3 B^(D-3)_(i-1) - B^(D-3)_i).
template <int D, int Order>
inline void pairBernstein(double s, Pair* b, Pair* db, Pair* ddb, Pair* dddb) {
  constexpr int count = pairsPerRow(D);
  const double r = 1.0 - s;
  const double s2 = s * s;
  const double r2 = r * r;
  Pair powers[count];
  powers[0] = Pair{1.0, s};
  for (int k = 1; k < count; ++k) powers[k] = powers[k - 1] * s2;
  pairBasis<D, D>(powers, r, r2, b);
  if constexpr (Order >= 1) {
    Pair lower[count];
    pairBasis<D, D - 1>(powers, r, r2, lower);
    Pair previous = Pair{0.0, 0.0};
    for (int k = 0; k < count; ++k) {
      const Pair shifted = Pair{previous[1], lower[k][0]};  // (B_2k-1, B_2k)
      db[k] = static_cast<double>(D) * (shifted - lower[k]);
      previous = lower[k];
    }
  }
  if constexpr (Order >= 2) {
    Pair lower[count];
    pairBasis<D, D - 2>(powers, r, r2, lower);
    Pair previous = Pair{0.0, 0.0};
    for (int k = 0; k < count; ++k) {
      const Pair shifted = Pair{previous[1], lower[k][0]};
      ddb[k] = static_cast<double>(D * (D - 1)) * (previous - 2.0 * shifted + lower[k]);
      previous = lower[k];
    }
  }
  if constexpr (Order >= 3) {
    if constexpr (D < 3) {
      for (int k = 0; k < count; ++k) dddb[k] = Pair{0.0, 0.0};
    } else {
      Pair lower[count];
      pairBasis<D, D - 3>(powers, r, r2, lower);
      Pair beforePrevious = Pair{0.0, 0.0};
      Pair previous = Pair{0.0, 0.0};
      for (int k = 0; k < count; ++k) {
        const Pair third = Pair{beforePrevious[1], previous[0]};  // (B_2k-3, B_2k-2)
        const Pair first = Pair{previous[1], lower[k][0]};        // (B_2k-1, B_2k)
        dddb[k] = static_cast<double>(D * (D - 1) * (D - 2)) *
                  (third - 3.0 * previous + 3.0 * first - lower[k]);
        beforePrevious = previous;
        previous = lower[k];
      }
    }
  }
}

/// The s-direction stage of fixedPatch: out[.][c] from the rows combined by the t-basis (t0)
/// and its derivatives (t1, t2, t3), a pair of columns at a time.
template <int D, int Order>
inline void finishPatch(const Pair* bx, const Pair* dbx, const Pair* ddbx, const Pair* dddbx,
                        const Pair* t0, const Pair* t1, const Pair* t2, const Pair* t3, int c,
                        double out[10][3]) {
  constexpr int count = pairsPerRow(D);
  Pair v = bx[0] * t0[0];
  Pair gs = Pair{0.0, 0.0}, gt = gs, hss = gs, hst = gs, htt = gs;
  Pair sss = gs, sst = gs, stt = gs, ttt = gs;
  if constexpr (Order >= 1) {
    gs = dbx[0] * t0[0];
    gt = bx[0] * t1[0];
  }
  if constexpr (Order >= 2) {
    hss = ddbx[0] * t0[0];
    hst = dbx[0] * t1[0];
    htt = bx[0] * t2[0];
  }
  if constexpr (Order >= 3) {
    sss = dddbx[0] * t0[0];
    sst = ddbx[0] * t1[0];
    stt = dbx[0] * t2[0];
    ttt = bx[0] * t3[0];
  }
  for (int j = 1; j < count; ++j) {
    v += bx[j] * t0[j];
    if constexpr (Order >= 1) {
      gs += dbx[j] * t0[j];
      gt += bx[j] * t1[j];
    }
    if constexpr (Order >= 2) {
      hss += ddbx[j] * t0[j];
      hst += dbx[j] * t1[j];
      htt += bx[j] * t2[j];
    }
    if constexpr (Order >= 3) {
      sss += dddbx[j] * t0[j];
      sst += ddbx[j] * t1[j];
      stt += dbx[j] * t2[j];
      ttt += bx[j] * t3[j];
    }
  }
  out[0][c] = v[0] + v[1];
  out[1][c] = gs[0] + gs[1];
  out[2][c] = gt[0] + gt[1];
  out[3][c] = hss[0] + hss[1];
  out[4][c] = hst[0] + hst[1];
  out[5][c] = htt[0] + htt[1];
  if constexpr (Order >= 3) {
    out[6][c] = sss[0] + sss[1];
    out[7][c] = sst[0] + sst[1];
    out[8][c] = stt[0] + stt[1];
    out[9][c] = ttt[0] + ttt[1];
  }
}

/// A tensor-product Bézier patch of bidegree (D, D) over the unit square at (s, t): value and
/// derivatives in out[0] = value, [1] = d/ds, [2] = d/dt, [3] = d2/ds2, [4] = d2/dsdt,
/// [5] = d2/dt2, [6] = d3/ds3, [7] = d3/ds2dt, [8] = d3/dsdt2, [9] = d3/dt3 (as far as Order
/// asks), each with x, y, z. Controls: three blocks (x, y, z) of
/// D + 1 rows of equal t-index, each row the D + 1 values of increasing s-index padded to
/// 2 pairsPerRow(D) doubles (the padding is never read into a result: its basis values are 0).
/// The rows are combined a pair of columns at a time.
template <int D, int Order>
void fixedPatch(const double* controls, double s, double t, double out[10][3]) {
  constexpr int m = D + 1;
  constexpr int count = pairsPerRow(D);
  Pair bx[count], dbx[count], ddbx[count], dddbx[count];
  Pair by[count], dby[count], ddby[count], dddby[count];
  pairBernstein<D, Order>(s, bx, dbx, ddbx, dddbx);
  pairBernstein<D, Order>(t, by, dby, ddby, dddby);
  for (int c = 0; c < 3; ++c) {
    const Pair* block = reinterpret_cast<const Pair*>(controls) + c * m * count;
    // t0 .. t3: the rows weighted by the t-basis and its derivatives.
    Pair t0[count], t1[count], t2[count], t3[count];
    for (int j = 0; j < count; ++j) {
      const Pair row = block[j];
      t0[j] = by[0][0] * row;
      if constexpr (Order >= 1) t1[j] = dby[0][0] * row;
      if constexpr (Order >= 2) t2[j] = ddby[0][0] * row;
      if constexpr (Order >= 3) t3[j] = dddby[0][0] * row;
    }
    for (int k = 1; k < m; ++k) {
      const Pair* row = block + k * count;
      const double a = by[k / 2][k % 2];
      for (int j = 0; j < count; ++j) t0[j] += a * row[j];
      if constexpr (Order >= 1) {
        const double b = dby[k / 2][k % 2];
        for (int j = 0; j < count; ++j) t1[j] += b * row[j];
      }
      if constexpr (Order >= 2) {
        const double e = ddby[k / 2][k % 2];
        for (int j = 0; j < count; ++j) t2[j] += e * row[j];
      }
      if constexpr (Order >= 3) {
        const double f = dddby[k / 2][k % 2];
        for (int j = 0; j < count; ++j) t3[j] += f * row[j];
      }
    }
    finishPatch<D, Order>(bx, dbx, ddbx, dddbx, t0, t1, t2, t3, c, out);
  }
}

#if defined(__GNUC__) && defined(__x86_64__)
#define D2VDB_WIDE_PATCH 1
/// Four doubles in one AVX register (may alias double, a double's alignment).
typedef double Quad __attribute__((vector_size(32), aligned(8), may_alias));

/// fixedPatch with the rows combined four columns at a time (AVX2, for processors that have
/// it). The same operations on every element in the same order, so the same results to the bit
/// (no fused multiply-add: the target adds none and ISO C++ mode does not contract).
template <int D, int Order>
__attribute__((target("avx2"))) void fixedPatchWide(const double* controls, double s, double t,
                                                    double out[10][3]) {
  constexpr int m = D + 1;
  constexpr int count = pairsPerRow(D);
  constexpr int quads = count / 2;       // whole quads per row
  constexpr bool tail = count % 2 != 0;  // and one pair after them
  Pair bx[count], dbx[count], ddbx[count], dddbx[count];
  Pair by[count], dby[count], ddby[count], dddby[count];
  pairBernstein<D, Order>(s, bx, dbx, ddbx, dddbx);
  pairBernstein<D, Order>(t, by, dby, ddby, dddby);
  for (int c = 0; c < 3; ++c) {
    const double* block = controls + c * m * 2 * count;
    constexpr int quadCount = quads > 0 ? quads : 1;
    Quad q0[quadCount], q1[quadCount], q2[quadCount], q3[quadCount];
    Pair p0 = Pair{0.0, 0.0}, p1 = p0, p2 = p0, p3 = p0;
    for (int k = 0; k < m; ++k) {
      const Quad* row = reinterpret_cast<const Quad*>(block + k * 2 * count);
      const Pair* rest = reinterpret_cast<const Pair*>(block + k * 2 * count) + 2 * quads;
      const double a = by[k / 2][k % 2];
      const double b = dby[k / 2][k % 2];
      const double e = ddby[k / 2][k % 2];
      const double f = Order >= 3 ? dddby[k / 2][k % 2] : 0.0;
      for (int j = 0; j < quads; ++j) {
        if (k == 0) {
          q0[j] = a * row[j];
          if constexpr (Order >= 1) q1[j] = b * row[j];
          if constexpr (Order >= 2) q2[j] = e * row[j];
          if constexpr (Order >= 3) q3[j] = f * row[j];
        } else {
          q0[j] += a * row[j];
          if constexpr (Order >= 1) q1[j] += b * row[j];
          if constexpr (Order >= 2) q2[j] += e * row[j];
          if constexpr (Order >= 3) q3[j] += f * row[j];
        }
      }
      if constexpr (tail) {
        if (k == 0) {
          p0 = a * rest[0];
          if constexpr (Order >= 1) p1 = b * rest[0];
          if constexpr (Order >= 2) p2 = e * rest[0];
          if constexpr (Order >= 3) p3 = f * rest[0];
        } else {
          p0 += a * rest[0];
          if constexpr (Order >= 1) p1 += b * rest[0];
          if constexpr (Order >= 2) p2 += e * rest[0];
          if constexpr (Order >= 3) p3 += f * rest[0];
        }
      }
    }
    Pair t0[count], t1[count], t2[count], t3[count];
    for (int j = 0; j < quads; ++j) {
      t0[2 * j] = Pair{q0[j][0], q0[j][1]};
      t0[2 * j + 1] = Pair{q0[j][2], q0[j][3]};
      if constexpr (Order >= 1) {
        t1[2 * j] = Pair{q1[j][0], q1[j][1]};
        t1[2 * j + 1] = Pair{q1[j][2], q1[j][3]};
      }
      if constexpr (Order >= 2) {
        t2[2 * j] = Pair{q2[j][0], q2[j][1]};
        t2[2 * j + 1] = Pair{q2[j][2], q2[j][3]};
      }
      if constexpr (Order >= 3) {
        t3[2 * j] = Pair{q3[j][0], q3[j][1]};
        t3[2 * j + 1] = Pair{q3[j][2], q3[j][3]};
      }
    }
    if constexpr (tail) {
      t0[count - 1] = p0;
      t1[count - 1] = p1;
      t2[count - 1] = p2;
      t3[count - 1] = p3;
    }
    finishPatch<D, Order>(bx, dbx, ddbx, dddbx, t0, t1, t2, t3, c, out);
  }
}
#endif

/// A fixed-bidegree patch function (fixedPatch's arguments).
using PatchFunction = void (*)(const double*, double, double, double[10][3]);

/// The patch functions of bidegrees 2 + Offsets: fixedPatchWide where Wide, else fixedPatch.
template <int Order, bool Wide, int... Offsets>
constexpr std::array<PatchFunction, sizeof...(Offsets)> patchFunctions(
    std::integer_sequence<int, Offsets...>) {
#ifdef D2VDB_WIDE_PATCH
  if constexpr (Wide) return {&fixedPatchWide<2 + Offsets, Order>...};
#endif
  return {&fixedPatch<2 + Offsets, Order>...};
}

/// A patch of bidegree d (2..kMaxBidegree; any other d as kMaxBidegree), controls and out as for
/// fixedPatch: its fixed-bidegree function, the wide one where the processor has AVX2, by one
/// indirect call through a table of them.
template <int Order>
void patch(int d, const double* controls, double s, double t, double out[10][3]) {
  constexpr auto bidegrees = std::make_integer_sequence<int, kMaxBidegree - 1>();
  const auto index = static_cast<unsigned>(d - 2);
  const unsigned at = index < kMaxBidegree - 2 ? index : kMaxBidegree - 2;
#ifdef D2VDB_WIDE_PATCH
  static constexpr std::array<PatchFunction, kMaxBidegree - 1> wideFunctions =
      patchFunctions<Order, true>(bidegrees);
  static const bool wide = __builtin_cpu_supports("avx2");
  if (wide) return wideFunctions[at](controls, s, t, out);
#endif
  static constexpr std::array<PatchFunction, kMaxBidegree - 1> functions =
      patchFunctions<Order, false>(bidegrees);
  functions[at](controls, s, t, out);
}

/// Chart point jets from canonical point jets, with the exact linear map at the centre of a
/// degree-6 chart (where the polar form has no derivative but the map is a rotation).
template <int Order>
bool chartJets(const PolarMap& map, int degree, const Jet<Order>& zx, const Jet<Order>& zy, int k,
               Jet<Order>& px, Jet<Order>& py) {
  if constexpr (Order > 0) {
    if (zx.v == 0.0 && zy.v == 0.0) {
      if (degree != 6) return false;
      const double angle = map.sector * k;
      const double c = map.radiusScale * std::cos(angle);
      const double s = map.radiusScale * std::sin(angle);
      px = c * zx - s * zy;
      py = s * zx + c * zy;
      return true;
    }
  }
  map.toChart(zx, zy, k, px, py);
  return true;
}

/// The canonical point of corner `corner` from barycentric jets.
template <int Order>
void canonicalJets(const Jet<Order> bary[3], int corner, Jet<Order>& zx, Jet<Order>& zy) {
  const Jet<Order>& next = bary[(corner + 1) % 3];
  const Jet<Order>& after = bary[(corner + 2) % 3];
  zx = next + 0.5 * after;
  zy = kCos30 * after;
}

Eigen::Vector3d toVector(const double* xyz) {
  return {xyz[0], xyz[1], xyz[2]};
}

}  // namespace

SmoothPoint surfaceGeometry(const SmoothDerivatives& x) {
  SmoothPoint result;
  result.position = x.position;
  const Eigen::Vector3d cross = x.d[0].cross(x.d[1]);
  const Eigen::Vector3d n = cross.normalized();
  result.normal = n;
  // Orthonormal tangent frame t1 = X_s / |X_s|, t2 = n x t1; C = [t1 t2]^T [X_s X_t] (upper
  // triangular); second fundamental form in the frame: C^-T II C^-1.
  const Eigen::Vector3d t1 = x.d[0].normalized();
  const Eigen::Vector3d t2 = n.cross(t1);
  const double c00 = x.d[0].norm();
  const double c01 = t1.dot(x.d[1]);
  const double c11 = t2.dot(x.d[1]);
  const double e = x.dd[0].dot(n);
  const double f = x.dd[1].dot(n);
  const double g = x.dd[2].dot(n);
  // M = C^-1 = [[1/c00, -c01/(c00 c11)], [0, 1/c11]]; II_o = M^T II M.
  const double m00 = 1.0 / c00;
  const double m01 = -c01 / (c00 * c11);
  const double m11 = 1.0 / c11;
  const double a = m00 * m00 * e;
  const double b = m00 * (m01 * e + m11 * f);
  const double c = m01 * m01 * e + 2.0 * m01 * m11 * f + m11 * m11 * g;
  // Curvatures with the sign convention k > 0 where the surface bends away from n: S = -II_o.
  const double sa = -a;
  const double sb = -b;
  const double sc = -c;
  const double mean = 0.5 * (sa + sc);
  // sqrt, not std::hypot: squared curvatures do not overflow, and hypot's guard would cost more
  // than the rest of this function (BENCHMARKS.md, "fewer copies").
  const double halfAcross = 0.5 * (sa - sc);
  const double radius = std::sqrt(halfAcross * halfAcross + sb * sb);
  result.k1 = mean + radius;
  result.k2 = mean - radius;
  // e1 at the angle phi = atan2(2 sb, sa - sc) / 2 in (-pi/2, pi/2] from t1, by the half-angle
  // formulas from cos 2 phi = (sa - sc) / R, sin 2 phi = 2 sb / R (R = 2 radius), each from the
  // side where it does not cancel; t1 at an umbilic (R = 0).
  const double across = sa - sc;
  const double twiceRadius = 2.0 * radius;
  double cosine = 1.0, sine = 0.0;
  if (twiceRadius > 0.0) {
    if (across >= 0.0) {
      cosine = std::sqrt((twiceRadius + across) / (2.0 * twiceRadius));
      sine = sb / (twiceRadius * cosine);
    } else {
      sine = std::copysign(std::sqrt((twiceRadius - across) / (2.0 * twiceRadius)), sb);
      cosine = sb / (twiceRadius * sine);
    }
  }
  result.e1 = (cosine * t1 + sine * t2).normalized();
  result.e2 = n.cross(result.e1);
  return result;
}

// ------------------------------------------------------------------------------------------------

struct PseudoManifold::DegreeFit {
  int degree = 0;
  int bidegree = 0;
  PolarMap map;
  std::vector<Eigen::Vector2d> canonical;  ///< per sample, in its sector's corner frame
  std::vector<int> sectorStart;            ///< samples of sector k: [sectorStart[k], [k + 1])
  /// (bidegree + 1)^2 x samples, row-major (one contiguous row per coefficient)
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> pseudoInverse;
  double condition = 0.0;

  DegreeFit(int n, int d, int samplesPerControl) : degree(n), bidegree(d), map(n) {
    const double radius = map.chartRadius;
    const int grid = samplesPerControl * (d + 1);
    struct Sample {
      int sector;
      Eigen::Vector2d p;
      Eigen::Vector2d z;
    };
    std::vector<Sample> samples;
    for (int i = 0; i < grid; ++i) {
      for (int j = 0; j < grid; ++j) {
        const Eigen::Vector2d p(-radius + (i + 0.5) * 2.0 * radius / grid,
                                -radius + (j + 0.5) * 2.0 * radius / grid);
        if (p.norm() >= radius) continue;
        int k = 0;
        const Eigen::Vector2d z = map.toCanonical(p, n, k);
        samples.push_back({k, p, z});
      }
    }
    std::stable_sort(samples.begin(), samples.end(),
                     [](const Sample& x, const Sample& y) { return x.sector < y.sector; });
    sectorStart.assign(n + 1, 0);
    for (const Sample& s : samples) ++sectorStart[s.sector + 1];
    for (int k = 0; k < n; ++k) sectorStart[k + 1] += sectorStart[k];
    const int count = static_cast<int>(samples.size());
    const int unknowns = (d + 1) * (d + 1);
    Eigen::MatrixXd design(count, unknowns);
    for (int s = 0; s < count; ++s) {
      canonical.push_back(samples[s].z);
      const BernsteinBasisValues bx =
          bernsteinBasisValues(d, (samples[s].p.x() + radius) / (2.0 * radius));
      const BernsteinBasisValues by =
          bernsteinBasisValues(d, (samples[s].p.y() + radius) / (2.0 * radius));
      for (int j = 0; j <= d; ++j) {
        for (int k = 0; k <= d; ++k) design(s, k * (d + 1) + j) = bx[j] * by[k];
      }
    }
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(design);
    const Eigen::MatrixXd r =
        qr.matrixQR().topLeftCorner(unknowns, unknowns).triangularView<Eigen::Upper>();
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(count, unknowns);
    pseudoInverse = r.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd(q.transpose()));
    // cond(design) = cond(R).
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(r);
    const auto& sv = svd.singularValues();
    condition = sv[0] / sv[sv.size() - 1];
  }

  /// Scratch space of fitChart(), reused from one vertex to the next.
  struct Scratch {
    Eigen::MatrixX3d samples;
    Eigen::MatrixX3d fitted;
    std::vector<Eigen::Vector3d> bary;
    std::vector<Eigen::Vector3d> positions;
  };

  /// Fits the shape function of `vertex` (of this degree) to `source`: the source's points at
  /// the samples through the chart's polar map, then one product with the pseudo-inverse. Writes
  /// the control points to `out` in fixedPatch's padded layout (the padding is not written).
  void fitChart(const HalfEdgeMesh& mesh, const SourceSurface& source, Index vertex,
                Scratch& scratch, double* out) const {
    const int count = static_cast<int>(canonical.size());
    scratch.samples.resize(count, 3);
    const Eigen::Vector3d center = mesh.position(vertex);
    for (int k = 0; k < degree; ++k) sampleSector(mesh, source, vertex, k, center, scratch);
    // Fitting offsets from the vertex keeps round-off relative to the chart's size (the fit
    // reproduces constants, so the offset comes back exactly).
    // One dot product per coefficient (row-major pseudo-inverse, column samples): no packing of
    // the large matrix for a three-column product.
    scratch.fitted.noalias() = pseudoInverse.lazyProduct(scratch.samples);
    // Coefficient k (d + 1) + j (k: t-index, j: s-index) to row k, column j of the padded
    // layout.
    const int m = bidegree + 1;
    const int width = 2 * pairsPerRow(bidegree);
    for (int axis = 0; axis < 3; ++axis) {
      for (int k = 0; k < m; ++k) {
        for (int j = 0; j < m; ++j) {
          out[(axis * m + k) * width + j] = scratch.fitted(k * m + j, axis) + center[axis];
        }
      }
    }
  }

  /// The rows of scratch.samples of sector k of `vertex`: the source's points there minus
  /// `center`, at the samples' barycentric coordinates in the sector's face.
  void sampleSector(const HalfEdgeMesh& mesh, const SourceSurface& source, Index vertex, int k,
                    const Eigen::Vector3d& center, Scratch& scratch) const {
    const int first = sectorStart[k];
    const int last = sectorStart[k + 1];
    if (first == last) return;
    const Index halfEdge = mesh.ring(vertex, k);
    const int corner = static_cast<int>(halfEdge % 3);
    std::vector<Eigen::Vector3d>& bary = scratch.bary;
    std::vector<Eigen::Vector3d>& positions = scratch.positions;
    bary.resize(static_cast<std::size_t>(last - first));
    positions.resize(bary.size());
    for (int s = first; s < last; ++s) {
      const Eigen::Vector3d local = detail::cornerBary(canonical[s]);
      Eigen::Vector3d& b = bary[static_cast<std::size_t>(s - first)];
      b[corner] = local[0];
      b[(corner + 1) % 3] = local[1];
      b[(corner + 2) % 3] = local[2];
    }
    source.positions(HalfEdgeMesh::face(halfEdge), bary.data(), bary.size(), positions.data());
    for (int s = first; s < last; ++s) {
      scratch.samples.row(s) =
          (positions[static_cast<std::size_t>(s - first)] - center).transpose();
    }
  }
};

// ------------------------------------------------------------------------------------------------

/// Evaluation with derivatives of order `Order` (0 to 3) with respect to two parameters.
template <int Order>
struct PseudoManifold::Evaluator {
  const PseudoManifold& pps;

  /// psi_v composed with chart point jets (px, py). `identity`: px and py are the independent
  /// variables (the chart's own coordinates), so the chain rule is the identity.
  Jet3<Order> shape(Index vertex, const Jet<Order>& px, const Jet<Order>& py,
                    bool identity = false) const {
    const int d = pps.bidegree(vertex);
    const double radius = pps.fitFor(pps.mesh_->degree(vertex)).map.chartRadius;
    const double* controls = pps.controls_.data() + pps.controlOffset_[vertex];
    const double inv = 0.5 / radius;
    double result[10][3];
    patch<Order>(d, controls, (px.v + radius) * inv, (py.v + radius) * inv, result);
    const double* value = result[0];
    const double* gx = result[1];
    const double* gy = result[2];
    const double* hxx = result[3];
    const double* hxy = result[4];
    const double* hyy = result[5];
    Jet3<Order> out;
    out.v = toVector(value);
    if constexpr (Order >= 1) {
      if (identity) {
        // The chain rule below with px.d = (1, 0), py.d = (0, 1) and no higher derivatives:
        // the same values (only the signs of zeros could differ).
        out.d[0] = inv * toVector(gx);
        out.d[1] = inv * toVector(gy);
        if constexpr (Order >= 2) {
          const double inv2 = inv * inv;
          out.h[0] = inv2 * toVector(hxx);
          out.h[1] = inv2 * toVector(hxy);
          out.h[2] = inv2 * toVector(hyy);
          if constexpr (Order >= 3) {
            const double inv3 = inv2 * inv;
            for (int m = 0; m < 4; ++m) out.t[m] = inv3 * toVector(result[6 + m]);
          }
        }
        return out;
      }
      const Eigen::Vector3d psiX = inv * toVector(gx);
      const Eigen::Vector3d psiY = inv * toVector(gy);
      for (int a = 0; a < 2; ++a) out.d[a] = psiX * px.d[a] + psiY * py.d[a];
      if constexpr (Order >= 2) {
        const double inv2 = inv * inv;
        const Eigen::Vector3d psiXX = inv2 * toVector(hxx);
        const Eigen::Vector3d psiXY = inv2 * toVector(hxy);
        const Eigen::Vector3d psiYY = inv2 * toVector(hyy);
        const int pairs[3][2] = {{0, 0}, {0, 1}, {1, 1}};
        for (int m = 0; m < 3; ++m) {
          const int a = pairs[m][0];
          const int b = pairs[m][1];
          out.h[m] = psiXX * (px.d[a] * px.d[b]) + psiXY * (px.d[a] * py.d[b] + py.d[a] * px.d[b]) +
                     psiYY * (py.d[a] * py.d[b]) + psiX * px.h[m] + psiY * py.h[m];
        }
        if constexpr (Order >= 3) {
          const double inv3 = inv2 * inv;
          const Eigen::Vector3d psiXXX = inv3 * toVector(result[6]);
          const Eigen::Vector3d psiXXY = inv3 * toVector(result[7]);
          const Eigen::Vector3d psiXYY = inv3 * toVector(result[8]);
          const Eigen::Vector3d psiYYY = inv3 * toVector(result[9]);
          for (int m = 0; m < 4; ++m) {
            out.t[m] = detail::chainThird<Eigen::Vector3d>(m, psiX, psiY, psiXX, psiXY, psiYY,
                                                           psiXXX, psiXXY, psiXYY, psiYYY, px, py);
          }
        }
      }
    }
    return out;
  }

  /// gamma_v composed with chart point jets (`identity`: as in shape(); `norm`: |p| as a jet,
  /// when known).
  Jet<Order> weight(Index vertex, const Jet<Order>& px, const Jet<Order>& py, bool identity = false,
                    const Jet<Order>* norm = nullptr) const {
    const double radius = pps.fitFor(pps.mesh_->degree(vertex)).map.chartRadius;
    const double rr = px.v * px.v + py.v * py.v;
    if (rr <= (kBumpInner * radius) * (kBumpInner * radius)) return Jet<Order>::constant(1.0);
    if constexpr (Order >= 3) {
      if (norm != nullptr) {
        const Jet<Order> t = (1.0 / radius) * *norm;
        const BumpValue xi = chartBump(t.v);
        return t.apply(xi.value, xi.first, xi.second, xi.third);
      }
      if (identity) {
        // t = |p| / radius from the derivatives of r = |p| in closed form.
        const Jet<Order> t = detail::radiusJetOfVariables(px.v, py.v, radius);
        const BumpValue xi = chartBump(t.v);
        return t.apply(xi.value, xi.first, xi.second, xi.third);
      }
    }
    const Jet<Order> t = (1.0 / radius) * sqrt(px * px + py * py);
    const BumpValue xi = chartBump(t.v);
    return t.apply(xi.value, xi.first, xi.second, xi.third);
  }

  /// The blended surface over the given chart point jets of the active corners; the jets of
  /// corner `identityCorner` (-1: none) are the independent variables; norms[i], where
  /// haveNorm[i], is |p_i| as a jet (used at Order 3).
  Jet3<Order> blend(const Index vertices[3], const Jet<Order> px[3], const Jet<Order> py[3],
                    const bool active[3], int identityCorner = -1,
                    const Jet<Order>* norms = nullptr, const bool* haveNorm = nullptr) const {
    Jet3<Order> numerator;
    Jet<Order> denominator;
    if constexpr (Order >= 3) {
      // With the normalised weights u_i = w_i / sum_j w_j, which add up to 1, the surface is
      // psi_last + sum over the other contributing charts of u_i (psi_i - psi_last): one product
      // rule fewer than the weighted sum and no quotient of points; one contributing chart gives
      // its shape function (no weight derivatives).
      Jet<Order> w[3];
      int contributing[3];
      int count = 0;
      for (int i = 0; i < 3; ++i) {
        if (!active[i]) continue;
        w[i] = weight(vertices[i], px[i], py[i], i == identityCorner,
                      norms != nullptr && haveNorm[i] ? &norms[i] : nullptr);
        if (w[i].v == 0.0) continue;  // beyond the cut-off: no contribution, no derivatives
        contributing[count++] = i;
      }
      const int last = contributing[count - 1];
      Jet3<Order> out = shape(vertices[last], px[last], py[last], last == identityCorner);
      if (count == 1) return out;
      Jet<Order> total = w[contributing[0]];
      for (int j = 1; j < count; ++j) total = total + w[contributing[j]];
      const double inverse = 1.0 / total.v;
      const Jet<Order> reciprocal =
          total.apply(inverse, -inverse * inverse, 2.0 * inverse * inverse * inverse,
                      -6.0 * inverse * inverse * inverse * inverse);
      const Jet3<Order> base = out;
      for (int j = 0; j + 1 < count; ++j) {
        const int i = contributing[j];
        Jet3<Order> difference = shape(vertices[i], px[i], py[i], i == identityCorner);
        difference.v -= base.v;
        for (int a = 0; a < 2; ++a) difference.d[a] -= base.d[a];
        for (int a = 0; a < 3; ++a) difference.h[a] -= base.h[a];
        for (int a = 0; a < 4; ++a) difference.t[a] -= base.t[a];
        detail::addProduct(out, w[i] * reciprocal, difference);
      }
      return out;
    }
    for (int i = 0; i < 3; ++i) {
      if (!active[i]) continue;
      const Jet<Order> w = weight(vertices[i], px[i], py[i]);
      if (w.v == 0.0) continue;  // beyond the cut-off: no contribution, no derivatives
      denominator = denominator + w;
      detail::addProduct(numerator, w, shape(vertices[i], px[i], py[i], i == identityCorner));
    }
    return detail::divide(numerator, denominator);
  }

  /// Derivatives with respect to the face's (b1, b2). False at a corner of degree != 6.
  bool face(const FacePoint& point, Jet3<Order>& out) const {
    const HalfEdgeMesh& mesh = *pps.mesh_;
    Jet<Order> bary[3];
    bary[1] = Jet<Order>::variable(point.bary[1], 0);
    bary[2] = Jet<Order>::variable(point.bary[2], 1);
    bary[0] = Jet<Order>::constant(1.0) - bary[1] - bary[2];
    bary[0].v = point.bary[0];
    Index vertices[3];
    Jet<Order> px[3], py[3];
    bool active[3];
    for (int i = 0; i < 3; ++i) {
      const Index halfEdge = 3 * point.face + static_cast<Index>(i);
      vertices[i] = mesh.from(halfEdge);
      active[i] = ChartAtlas::inChart(point.bary, i);
      if (!active[i]) continue;
      const int n = mesh.degree(vertices[i]);
      Jet<Order> zx, zy;
      canonicalJets(bary, i, zx, zy);
      if (!chartJets(pps.fitFor(n).map, n, zx, zy, mesh.ringIndex(halfEdge), px[i], py[i])) {
        return false;
      }
    }
    out = blend(vertices, px, py, active);
    return true;
  }

  /// Derivatives with respect to the chart coordinates of corner `center` (the point must lie in
  /// that chart).
  /// When `chartPoint` is given it receives the point's coordinates in that chart (as
  /// ChartAtlas::toChart gives them).
  /// When `knownChartPoint` is given it is taken as the point's coordinates in that chart (a
  /// point the atlas mapped to `point`, equal to the map's image up to round-off), saving the
  /// polar map.
  Jet3<Order> chart(const FacePoint& point, int center, Eigen::Vector2d* chartPoint = nullptr,
                    const Eigen::Vector2d* knownChartPoint = nullptr) const {
    const HalfEdgeMesh& mesh = *pps.mesh_;
    Index vertices[3];
    Jet<Order> px[3], py[3];
    bool active[3];
    const Index centerHalfEdge = 3 * point.face + static_cast<Index>(center);
    vertices[center] = mesh.from(centerHalfEdge);
    const int nc = mesh.degree(vertices[center]);
    const PolarMap& centerMap = pps.fitFor(nc).map;
    const int kc = mesh.ringIndex(centerHalfEdge);
    const Eigen::Vector2d z = detail::canonicalPoint(point.bary, center);
    const Eigen::Vector2d p =
        knownChartPoint != nullptr ? *knownChartPoint : centerMap.toChart(z, kc);
    if (chartPoint != nullptr) *chartPoint = p;
    px[center] = Jet<Order>::variable(p.x(), 0);
    py[center] = Jet<Order>::variable(p.y(), 1);
    active[center] = true;
    bool haveBary = false;
    Jet<Order> bary[3];
    Jet<Order> norms[3];
    bool haveNorm[3] = {false, false, false};
    for (int i = 0; i < 3; ++i) {
      if (i == center) continue;
      const Index halfEdge = 3 * point.face + static_cast<Index>(i);
      vertices[i] = mesh.from(halfEdge);
      active[i] = ChartAtlas::inChart(point.bary, i);
      if (!active[i]) continue;
      if (!haveBary) {
        // Barycentric jets of the face from the centre chart's coordinates (p != 0 here: another
        // chart contains the point, so it is at least 1 - cos(pi/6) from the centre).
        Jet<Order> zx, zy;
        centerMap.toCanonicalAt(px[center], py[center], kc, z, zx, zy, true);
        const Jet<Order> after = (1.0 / kCos30) * zy;
        const Jet<Order> next = zx - 0.5 * after;
        bary[(center + 1) % 3] = next;
        bary[(center + 2) % 3] = after;
        bary[center] = Jet<Order>::constant(1.0) - next - after;
        haveBary = true;
      }
      const int n = mesh.degree(vertices[i]);
      Jet<Order> zx, zy;
      canonicalJets(bary, i, zx, zy);
      if constexpr (Order >= 3) {
        haveNorm[i] = pps.fitFor(n).map.toChartWithNorm(zx, zy, mesh.ringIndex(halfEdge), px[i],
                                                        py[i], norms[i]);
        if (haveNorm[i]) continue;
      }
      pps.fitFor(n).map.toChart(zx, zy, mesh.ringIndex(halfEdge), px[i], py[i]);
    }
    return blend(vertices, px, py, active, center, norms, haveNorm);
  }
};

// ------------------------------------------------------------------------------------------------

namespace {

/// InputError unless the construction parameters lie in their ranges.
void requireOptions(const PseudoManifoldOptions& options) {
  if (options.maxBidegree < 2 || options.maxBidegree > kMaxBidegree) {
    throw InputError("the shape functions' bidegree cap must lie in 2.." +
                     std::to_string(kMaxBidegree) + ", not " + std::to_string(options.maxBidegree));
  }
  if (options.samplesPerControl < 2 || options.samplesPerControl > 8) {
    throw InputError("the fitting grid needs 2..8 samples per control point, not " +
                     std::to_string(options.samplesPerControl));
  }
}

}  // namespace

PseudoManifold::PseudoManifold(const SourceSurface& source, const PseudoManifoldOptions& options,
                               const ProgressCallback& progress)
    : mesh_(source.sharedMesh()), atlas_(*mesh_), options_(options), sourceName_(source.name()) {
  requireOptions(options);
  const HalfEdgeMesh& mesh = *mesh_;
  const std::size_t vertexCount = mesh.vertexCount();
  // One least-squares factorisation per degree present.
  fits_.resize(static_cast<std::size_t>(mesh.maxDegree()) + 1);
  for (Index v = 0; v < vertexCount; ++v) {
    const int n = mesh.degree(v);
    if (n > 0 && !fits_[n]) {
      fits_[n] = sharedFit(n, std::min(n + 1, options.maxBidegree), options.samplesPerControl);
    }
  }
  controlOffset_.assign(vertexCount + 1, 0);
  for (Index v = 0; v < vertexCount; ++v) {
    const int n = mesh.degree(v);
    // (bidegree + 1) rows of 2 pairsPerRow(bidegree) doubles (fixedPatch's layout).
    const std::size_t count = n > 0 ? static_cast<std::size_t>((fits_[n]->bidegree + 1) * 2 *
                                                               pairsPerRow(fits_[n]->bidegree))
                                    : 0;
    controlOffset_[v + 1] = controlOffset_[v] + 3 * count;
  }
  const std::size_t bytes = controlOffset_[vertexCount] * sizeof(double);
  if (bytes > options.maxBytes) {
    throw InputError("the smooth surface of " + std::to_string(vertexCount) + " vertices needs " +
                     std::to_string(bytes >> 20) +
                     " MiB of control points, more than the limit of " +
                     std::to_string(options.maxBytes >> 20) +
                     " MiB; simplify the mesh or lower the bidegree cap");
  }
  controls_.assign(controlOffset_[vertexCount], 0.0);

  // Fit every chart (DegreeFit::fitChart). Blocks in sequence (for progress), vertices of a block
  // in parallel; each vertex writes only its own control points.
  const std::size_t blocks =
      std::max<std::size_t>(1, std::min<std::size_t>(100, vertexCount / 256));
  for (std::size_t block = 0; block < blocks; ++block) {
    const std::size_t begin = vertexCount * block / blocks;
    const std::size_t end = vertexCount * (block + 1) / blocks;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        DegreeFit::Scratch scratch;
                        for (std::size_t v = range.begin(); v != range.end(); ++v) {
                          const auto vertex = static_cast<Index>(v);
                          const int n = mesh.degree(vertex);
                          if (n == 0) continue;
                          fits_[n]->fitChart(mesh, source, vertex, scratch,
                                             controls_.data() + controlOffset_[v]);
                        }
                      });
    if (progress) progress("fitting charts", static_cast<double>(block + 1) / blocks);
  }
}

PseudoManifold::~PseudoManifold() = default;
PseudoManifold::PseudoManifold(PseudoManifold&&) noexcept = default;
PseudoManifold& PseudoManifold::operator=(PseudoManifold&&) noexcept = default;

std::shared_ptr<const PseudoManifold::DegreeFit> PseudoManifold::sharedFit(int degree, int bidegree,
                                                                           int samplesPerControl) {
  static std::mutex mutex;
  static std::map<std::array<int, 3>, std::shared_ptr<const DegreeFit>> fits;
  const std::array<int, 3> key = {degree, bidegree, samplesPerControl};
  const std::lock_guard<std::mutex> lock(mutex);
  std::shared_ptr<const DegreeFit>& fit = fits[key];
  if (!fit) fit = std::make_shared<const DegreeFit>(degree, bidegree, samplesPerControl);
  return fit;
}

const PseudoManifold::DegreeFit& PseudoManifold::fitFor(int degree) const {
  return *fits_[degree];
}

int PseudoManifold::bidegree(Index vertex) const {
  const int n = mesh_->degree(vertex);
  return n > 0 ? fits_[n]->bidegree : 0;
}

std::vector<Eigen::Vector3d> PseudoManifold::controlPoints(Index vertex) const {
  std::vector<Eigen::Vector3d> points;
  const int d = bidegree(vertex);
  if (d == 0) return points;
  const int m = d + 1;
  const int width = 2 * pairsPerRow(d);
  const double* base = controls_.data() + controlOffset_[vertex];
  for (int j = 0; j <= d; ++j) {
    for (int k = 0; k <= d; ++k) {
      const int i = k * width + j;
      points.emplace_back(base[i], base[m * width + i], base[2 * m * width + i]);
    }
  }
  return points;
}

double PseudoManifold::fitConditionNumber(int degree) const {
  if (degree < 0 || degree >= static_cast<int>(fits_.size()) || !fits_[degree]) return 0.0;
  return fits_[degree]->condition;
}

int PseudoManifold::fitSampleCount(int degree) const {
  if (degree < 0 || degree >= static_cast<int>(fits_.size()) || !fits_[degree]) return 0;
  return static_cast<int>(fits_[degree]->canonical.size());
}

Eigen::Vector3d PseudoManifold::shapeFunction(const ChartPoint& point) const {
  if (point.vertex >= mesh_->vertexCount() || mesh_->degree(point.vertex) == 0) {
    throw InputError("vertex " + std::to_string(point.vertex) + " has no chart");
  }
  const Evaluator<0> evaluator{*this};
  return evaluator.shape(point.vertex, Jet<0>::constant(point.p.x()), Jet<0>::constant(point.p.y()))
      .v;
}

double PseudoManifold::weight(const ChartPoint& point) const {
  if (point.vertex >= mesh_->vertexCount() || mesh_->degree(point.vertex) == 0) {
    throw InputError("vertex " + std::to_string(point.vertex) + " has no chart");
  }
  const double radius = fitFor(mesh_->degree(point.vertex)).map.chartRadius;
  return chartBump(point.p.norm() / radius).value;
}

Eigen::Vector3d PseudoManifold::position(const FacePoint& point) const {
  const Evaluator<0> evaluator{*this};
  Jet3<0> jet;
  evaluator.face(point, jet);
  return jet.v;
}

namespace {

/// The corner with the largest barycentric coordinate (the lowest such index on ties).
int nearestCorner(const Eigen::Vector3d& bary) {
  int best = 0;
  for (int i = 1; i < 3; ++i) {
    if (bary[i] > bary[best]) best = i;
  }
  return best;
}

template <int Order>
SmoothDerivatives toDerivatives(const Jet3<Order>& jet) {
  SmoothDerivatives out;
  out.position = jet.v;
  for (int i = 0; i < 2; ++i) out.d[i] = jet.d[i];
  for (int i = 0; i < 3; ++i) out.dd[i] = jet.h[i];
  return out;
}

SmoothThirdDerivatives toThirdDerivatives(const Jet3<3>& jet) {
  SmoothThirdDerivatives out;
  out.position = jet.v;
  for (int i = 0; i < 2; ++i) out.d[i] = jet.d[i];
  for (int i = 0; i < 3; ++i) out.dd[i] = jet.h[i];
  for (int i = 0; i < 4; ++i) out.ddd[i] = jet.t[i];
  return out;
}

}  // namespace

SmoothPoint PseudoManifold::evaluate(const FacePoint& point, Derivatives derivatives) const {
  if (point.face >= mesh_->faceCount()) {
    throw InputError("face " + std::to_string(point.face) + " does not exist (the mesh has " +
                     std::to_string(mesh_->faceCount()) + " faces)");
  }
  SmoothPoint result;
  const int center = nearestCorner(point.bary);
  switch (derivatives) {
    case Derivatives::None:
      result.position = position(point);
      return result;
    case Derivatives::First: {
      const Evaluator<1> evaluator{*this};
      Jet3<1> jet;
      // The face parametrisation is smooth away from the corners; at a corner use its chart.
      if (detail::canonicalPoint(point.bary, center).squaredNorm() < 1e-12 ||
          !evaluator.face(point, jet)) {
        jet = evaluator.chart(point, center);
      }
      result.position = jet.v;
      result.normal = jet.d[0].cross(jet.d[1]).normalized();
      return result;
    }
    case Derivatives::Second:
    default: {
      const Evaluator<2> evaluator{*this};
      return surfaceGeometry(toDerivatives(evaluator.chart(point, center)));
    }
  }
}

std::vector<SmoothPoint> PseudoManifold::evaluate(const std::vector<FacePoint>& points,
                                                  Derivatives derivatives) const {
  std::vector<SmoothPoint> results;
  evaluate(points, derivatives, results);
  return results;
}

void PseudoManifold::evaluate(const std::vector<FacePoint>& points, Derivatives derivatives,
                              std::vector<SmoothPoint>& results) const {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].face >= mesh_->faceCount()) {
      throw InputError("point " + std::to_string(i) + ": face " + std::to_string(points[i].face) +
                       " does not exist (the mesh has " + std::to_string(mesh_->faceCount()) +
                       " faces)");
    }
  }
  results.resize(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        results[i] = evaluate(points[i], derivatives);
                      }
                    });
}

namespace {

/// InputError unless `point` lies on a face of `mesh` and in the chart of its corner `corner`.
void requireChartPoint(const HalfEdgeMesh& mesh, const FacePoint& point, int corner) {
  if (point.face >= mesh.faceCount() || corner < 0 || corner > 2) {
    throw InputError("no such face or corner");
  }
  if (!ChartAtlas::inChart(point.bary, corner)) {
    throw InputError("the point does not lie in the chart of corner " + std::to_string(corner));
  }
}

}  // namespace

std::optional<SmoothDerivatives> PseudoManifold::faceDerivatives(const FacePoint& point) const {
  if (point.face >= mesh_->faceCount()) {
    throw InputError("face " + std::to_string(point.face) + " does not exist");
  }
  const Evaluator<2> evaluator{*this};
  Jet3<2> jet;
  if (!evaluator.face(point, jet)) return std::nullopt;
  return toDerivatives(jet);
}

SmoothDerivatives PseudoManifold::chartDerivatives(const FacePoint& point, int corner) const {
  requireChartPoint(*mesh_, point, corner);
  const Evaluator<2> evaluator{*this};
  return toDerivatives(evaluator.chart(point, corner));
}

SmoothThirdDerivatives PseudoManifold::chartThirdDerivatives(const FacePoint& point,
                                                             int corner) const {
  requireChartPoint(*mesh_, point, corner);
  const Evaluator<3> evaluator{*this};
  return toThirdDerivatives(evaluator.chart(point, corner));
}

PseudoManifold::Projection PseudoManifold::project(const Eigen::Vector3d& x, const FacePoint& start,
                                                   const SmoothProjectionOptions& options) const {
  if (!x.allFinite()) throw InputError("cannot project a non-finite point");
  if (start.face >= mesh_->faceCount()) {
    throw InputError("face " + std::to_string(start.face) + " does not exist");
  }
  Projection result;
  projectFrom(x, start, nullptr, options, result);
  return result;
}

PseudoManifold::Projection PseudoManifold::project(const Eigen::Vector3d& x,
                                                   const Projection& nearby,
                                                   const SmoothProjectionOptions& options) const {
  Projection result;
  project(x, nearby, options, result);
  return result;
}

void PseudoManifold::project(const Eigen::Vector3d& x, const Projection& nearby,
                             const SmoothProjectionOptions& options, Projection& result) const {
  if (!x.allFinite()) throw InputError("cannot project a non-finite point");
  if (nearby.point.face >= mesh_->faceCount() || nearby.chartCorner < 0 || nearby.chartCorner > 2 ||
      !nearby.chartPoint.allFinite()) {
    throw InputError("the projection to start from has no face " +
                     std::to_string(nearby.point.face) + " or corner " +
                     std::to_string(nearby.chartCorner));
  }
  if (&result == &nearby) {
    throw InputError("a projection cannot be written over the one it starts from");
  }
  projectFrom(x, nearby.point, &nearby, options, result);
}

namespace {

/// The cubic Taylor model of a surface at a point (derivatives `jet` and `third`, indexed as in
/// Jet) moved by `step`: position, first and second derivatives at the end (exact for a cubic).
inline __attribute__((always_inline)) Jet3<2> cubicTaylor(const Jet3<2>& jet,
                                                          const Eigen::Vector3d third[4],
                                                          const Eigen::Vector2d& step) {
  const double s[2] = {step.x(), step.y()};
  Jet3<2> moved;
  // Second derivatives: h_ab + t_abc s_c.
  for (int ab = 0; ab < 3; ++ab) moved.h[ab] = jet.h[ab] + third[ab] * s[0] + third[ab + 1] * s[1];
  // First: d_a + h_ab s_b + 1/2 t_abc s_b s_c = d_a + 1/2 (h_ab + moved h_ab) s_b.
  for (int a = 0; a < 2; ++a) {
    moved.d[a] =
        jet.d[a] + 0.5 * ((jet.h[a] + moved.h[a]) * s[0] + (jet.h[a + 1] + moved.h[a + 1]) * s[1]);
  }
  // Position: v + d_a s_a + 1/2 h_ab s_a s_b + 1/6 t_abc s_a s_b s_c.
  const Eigen::Vector3d hs[2] = {jet.h[0] * s[0] + jet.h[1] * s[1],
                                 jet.h[1] * s[0] + jet.h[2] * s[1]};
  const Eigen::Vector3d ts[2] = {
      (third[0] * s[0] + third[1] * s[1]) * s[0] + (third[1] * s[0] + third[2] * s[1]) * s[1],
      (third[1] * s[0] + third[2] * s[1]) * s[0] + (third[2] * s[0] + third[3] * s[1]) * s[1]};
  moved.v = jet.v + (jet.d[0] + 0.5 * hs[0] + ts[0] * (1.0 / 6.0)) * s[0] +
            (jet.d[1] + 0.5 * hs[1] + ts[1] * (1.0 / 6.0)) * s[1];
  return moved;
}

/// Newton's method on the distance from x to the cubic model (jet, third) from `move` (chart
/// coordinates relative to the model's origin), until a correction is below 1e-7 of `radius`
/// (the next would be below about 1e-13 of it), at most `iterations` corrections. `moved`
/// receives the model at the end. False when the model's Hessian of the distance is not positive
/// definite on the way or a correction is not finite (move and moved are then where it stopped).
bool minimizeCubicModel(const Jet3<2>& jet, const Eigen::Vector3d third[4],
                        const Eigen::Vector3d& x, double radius, int iterations,
                        Eigen::Vector2d& move, Jet3<2>& moved, double correction) {
  moved = cubicTaylor(jet, third, move);
  for (int k = 0; k < iterations && correction > 1e-7 * radius; ++k) {
    const Eigen::Vector3d r = moved.v - x;
    const double g0 = moved.d[0].dot(r), g1 = moved.d[1].dot(r);
    const double a = moved.d[0].dot(moved.d[0]) + moved.h[0].dot(r);
    const double b = moved.d[0].dot(moved.d[1]) + moved.h[1].dot(r);
    const double c = moved.d[1].dot(moved.d[1]) + moved.h[2].dot(r);
    const double determinant = a * c - b * b;
    if (!(a > 0.0 && determinant > 0.0)) return false;
    const Eigen::Vector2d delta((b * g1 - c * g0) / determinant, (b * g0 - a * g1) / determinant);
    if (!delta.allFinite()) return false;
    move += delta;
    moved = cubicTaylor(jet, third, move);
    correction = delta.norm();
  }
  return correction <= 1e-7 * radius;
}

template <int Order>
Jet3<Order> fromDerivatives(const SmoothDerivatives& x) {
  Jet3<Order> jet;
  jet.v = x.position;
  for (int i = 0; i < 2; ++i) jet.d[i] = x.d[i];
  for (int i = 0; i < 3; ++i) jet.h[i] = x.dd[i];
  return jet;
}

/// The jet moved by `step` along its second-order Taylor expansion: position and first
/// derivatives carried, second derivatives kept (SmoothProjectionOptions::extrapolateLastStep).
Jet3<2> quadraticTaylor(const Jet3<2>& jet, const Eigen::Vector2d& step) {
  const double a = step.x(), b = step.y();
  Jet3<2> moved = jet;
  moved.v += jet.d[0] * a + jet.d[1] * b +
             0.5 * (jet.h[0] * (a * a) + 2.0 * jet.h[1] * (a * b) + jet.h[2] * (b * b));
  moved.d[0] += jet.h[0] * a + jet.h[1] * b;
  moved.d[1] += jet.h[1] * a + jet.h[2] * b;
  return moved;
}

/// One iterate's step on |X - x|^2 / 2 in the chart of the iterate's corner (chart coordinates).
struct NewtonStep {
  double radius = 0.0;       ///< of that chart
  double value = 0.0;        ///< |X - x|^2 / 2 at the iterate
  Eigen::Vector2d gradient;  ///< of `value`
  Eigen::Vector2d step;      ///< at most maxStep long
  double maxStep = 0.0;
  double length = 0.0;    ///< |step| as clipped, before any first-step correction
  bool definite = false;  ///< a Newton step (positive definite Hessian), else Gauss-Newton
  bool clipped = false;   ///< shortened to maxStep
};

/// Fills newton.gradient, step, maxStep, length, definite and clipped for the iterate `jet` with
/// residual X - x (newton.radius given): Newton's step where the Hessian is positive definite
/// (a > 0 and a c - b^2 > 0; the step by the 2 x 2 inverse), else Gauss-Newton's (always a
/// descent step), kept inside the chart: at most half its radius. False when the step is not
/// finite (a degenerate point).
bool newtonStep(const Jet3<2>& jet, const Eigen::Vector3d& residual, NewtonStep& newton) {
  Eigen::Matrix2d jtj;
  jtj << jet.d[0].dot(jet.d[0]), jet.d[0].dot(jet.d[1]), jet.d[0].dot(jet.d[1]),
      jet.d[1].dot(jet.d[1]);
  newton.gradient = Eigen::Vector2d(jet.d[0].dot(residual), jet.d[1].dot(residual));
  const Eigen::Vector2d& gradient = newton.gradient;
  Eigen::Matrix2d hessian = jtj;
  hessian(0, 0) += jet.h[0].dot(residual);
  hessian(0, 1) += jet.h[1].dot(residual);
  hessian(1, 0) += jet.h[1].dot(residual);
  hessian(1, 1) += jet.h[2].dot(residual);
  const double determinant = hessian(0, 0) * hessian(1, 1) - hessian(0, 1) * hessian(0, 1);
  newton.definite = hessian(0, 0) > 0.0 && determinant > 0.0;
  newton.step =
      newton.definite
          ? Eigen::Vector2d(
                (hessian(0, 1) * gradient.y() - hessian(1, 1) * gradient.x()) / determinant,
                (hessian(0, 1) * gradient.x() - hessian(0, 0) * gradient.y()) / determinant)
          : Eigen::Vector2d(-jtj.ldlt().solve(gradient));
  if (!newton.step.allFinite()) return false;
  newton.maxStep = 0.5 * newton.radius;
  newton.clipped = newton.step.norm() > newton.maxStep;
  if (newton.clipped) newton.step *= newton.maxStep / newton.step.norm();
  newton.length = newton.step.norm();
  return true;
}

/// The length of the next Newton step after one of `length` that Newton's quadratic convergence
/// predicts: the ratio of this step to the square of the last one (`lastStep`), or a factor
/// 10 / radius for a first step (lastStep 0).
double predictedNextStep(double length, double lastStep, double radius) {
  return lastStep > 0.0 ? length * length * length / (lastStep * lastStep)
                        : 10.0 * length * length / radius;
}

}  // namespace

/// One run of projectFrom(): Newton's method as project() describes it. The iteration's state
/// lives here and each member function is one phase of an iteration; a phase that returns true
/// has ended the iteration, either with a step to the next iterate (current_) or with the
/// projection stopped (result converged or beyond). The projection is the hot path of the
/// smooth-surface field: run(), iterate(), endAt() and keepModel() are forced inline so that a
/// projection compiles to one function with one loop, its state in that function's frame.
class PseudoManifold::ProjectionRun {
 public:
  /// `result` may hold an earlier projection: every member not written by finish() is reset.
  ProjectionRun(const PseudoManifold& surface, const Eigen::Vector3d& x, const FacePoint& start,
                const Projection* nearby, const SmoothProjectionOptions& options,
                Projection& result)
      : surface_(surface),
        mesh_(*surface.mesh_),
        x_(x),
        nearby_(nearby),
        options_(options),
        result_(result),
        current_(start),
        previous_(start),
        known_(nearby != nullptr),
        center_(known_ ? nearby->chartCorner : 0) {
    result.firstStepMiss.reset();
    result.model.reset();
    result.iterations = 0;
    result.converged = false;
    result.beyond = false;
  }

  /// Iterates until the projection stops (at most 60 iterations), then writes the result.
  __attribute__((always_inline)) void run() {
    constexpr int kMaxIterations = 60;
    for (int iteration = 0; iteration < kMaxIterations && !stopped(); ++iteration) {
      iterate(iteration);
    }
    finish();
  }

 private:
  /// A Newton step after which quadratic convergence predicts one below this fraction of the
  /// chart radius is the last.
  static constexpr double kTolerance = 1e-12;

  bool stopped() const { return result_.converged || result_.beyond; }

  /// One iteration: the iterate's jet and Newton step, then the first phase that applies.
  __attribute__((always_inline)) void iterate(int iteration) {
    evaluateIterate();
    if (finalStep_) {
      // Evaluated where the converging step ended: the answer (an uphill step cannot happen
      // here, the step being far below anything the distance could resolve).
      result_.converged = true;
      return;
    }
    NewtonStep newton;
    newton.radius = surface_.fitFor(mesh_.degree(chartPoint_.vertex)).map.chartRadius;
    const Eigen::Vector3d residual = jet_.v - x_;
    newton.value = 0.5 * residual.squaredNorm();
    if (undoUphillStep(newton.value)) return;
    if (!newtonStep(jet_, residual, newton)) {
      result_.converged = true;  // a degenerate point: stay (the jet there is the answer)
      return;
    }
    if (newton.length <= 1e-12 * newton.radius) {
      result_.converged = true;  // `current_` and its jet are the answer
      return;
    }
    if (stopBeyond(newton, iteration) || finishOnModel(newton)) return;
    const bool fromNearby = iteration == 0 && nearby_ != nullptr;
    if (fromNearby && startFromNearbyModel(newton)) return;
    prepareFirstStep(newton, fromNearby);
    takeStep(newton);
  }

  /// The iterate's jet in the chart of its nearest corner (with third derivatives when wantThird_
  /// asks for them and the step there was not the last), or the nearby projection's at the start.
  void evaluateIterate() {
    haveThird_ = false;
    if (known_) {
      jet_ = fromDerivatives<2>(nearby_->derivatives);
      known_ = false;
      chartPoint_.vertex = mesh_.from(3 * current_.face + static_cast<Index>(center_));
      chartPoint_.p = nearby_->chartPoint;
    } else {
      center_ = nearestCorner(current_.bary);
      const Index vertex = mesh_.from(3 * current_.face + static_cast<Index>(center_));
      // A step taken in the chart of the same vertex: its end is the chart point already.
      const bool sameChart = stepEnd_ && stepEnd_->vertex == vertex;
      const Eigen::Vector2d* knownPoint = sameChart ? &stepEnd_->p : nullptr;
      if (wantThird_ && !finalStep_) {
        const Jet3<3> full =
            Evaluator<3>{surface_}.chart(current_, center_, &chartPoint_.p, knownPoint);
        jet_.v = full.v;
        for (int i = 0; i < 2; ++i) jet_.d[i] = full.d[i];
        for (int i = 0; i < 3; ++i) jet_.h[i] = full.h[i];
        for (int i = 0; i < 4; ++i) third_[i] = full.t[i];
        haveThird_ = true;
      } else {
        jet_ = Evaluator<2>{surface_}.chart(current_, center_, &chartPoint_.p, knownPoint);
      }
      chartPoint_.vertex = vertex;
      ++result_.iterations;
    }
    wantThird_ = false;
    stepEnd_.reset();
  }

  /// When the last (unchecked) Newton step went uphill, goes back to the iterate before it, to
  /// search carefully from there (true); else that iterate becomes the one to go back to.
  bool undoUphillStep(double value) {
    if (checkLast_ && value > previousValue_) {
      firstEnd_.reset();
      careful_ = true;
      checkLast_ = false;
      lastStep_ = 0.0;
      current_ = previous_;
      return true;
    }
    previous_ = current_;
    previousValue_ = value;
    return false;
  }

  /// Stops (beyond) when the distance is certainly above options_.stopBeyond.
  bool stopBeyond(const NewtonStep& newton, int iteration) {
    if (!(newton.definite && newton.length < 1e-2 * newton.radius &&
          2.0 * newton.value > options_.stopBeyond * options_.stopBeyond)) {
      return false;
    }
    // The quadratic model's minimum of |X - x|^2 is 2 value + gradient . step; four times that
    // decrease is a safe bound this close to the minimum.
    const double lowest = 2.0 * newton.value + 4.0 * newton.gradient.dot(newton.step);
    if (!(lowest > options_.stopBeyond * options_.stopBeyond)) return false;
    // Stopped at an iterate evaluated with third derivatives, or at the nearby footpoint found
    // on a cubic model: that model starts the neighbours (which may stop beyond on it without
    // an evaluation).
    if (haveThird_) {
      keepModel();
    } else if (iteration == 0 && nearby_ != nullptr && nearby_->model &&
               nearby_->model->origin.vertex == chartPoint_.vertex) {
      result_.model = nearby_->model;
    }
    result_.beyond = true;
    return true;
  }

  /// options_.cubicFinish at an iterate with third derivatives whose Newton step is short: the
  /// cubic model's minimum of the distance, by Newton's method on the model from the Newton step
  /// (the model's first iterate: at the iterate the model has the surface's gradient and
  /// Hessian), is the answer. Each iteration squares the correction: once a correction c is
  /// below 1e-7 of the radius the next (about 10 |c|^2 / radius) is below 1e-13 of it.
  bool finishOnModel(const NewtonStep& newton) {
    const double radius = newton.radius;
    if (!(haveThird_ && newton.definite && !newton.clipped &&
          newton.length <= options_.cubicFinishStep * radius &&
          (chartPoint_.p + newton.step).norm() < 0.98 * radius)) {
      return false;
    }
    Eigen::Vector2d move = newton.step;
    Jet3<2> moved;
    minimizeCubicModel(jet_, third_, x_, radius, 4, move, moved, newton.length);
    const Eigen::Vector2d p = chartPoint_.p + move;
    if (!(move.norm() <= 2.0 * newton.length && p.norm() < 0.99 * radius)) return false;
    keepModel();  // at the iterate, before endAt moves jet and chart point to the minimum
    endAt(p, moved);
    result_.converged = true;
    return true;
  }

  /// The first step from a nearby projection with a cubic model in this chart
  /// (options_.startFromModel): from the minimum of the distance to that model. There the
  /// projection stops beyond the band or converges when the model is certain enough, else the
  /// minimum is the first step, checked by the next iterate's distance; no plain Newton step, so
  /// it neither counts as tiny nor feeds the convergence prediction. False when no such minimum
  /// was found (the iteration goes on as without the model).
  bool startFromNearbyModel(const NewtonStep& newton) {
    if (!(options_.cubicFinish && options_.startFromModel && nearby_->model &&
          nearby_->model->origin.vertex == chartPoint_.vertex)) {
      return false;
    }
    const Projection::CubicModel& model = *nearby_->model;
    const double radius = newton.radius;
    Eigen::Vector2d move;
    Jet3<2> moved;
    if (!minimumOfNearbyModel(model, newton, move, moved)) return false;
    const Eigen::Vector2d p = model.origin.p + move;
    const double modelDistance = (moved.v - x_).norm();
    // Within 0.15 of the radius of the origin, a margin of 2 % of stopBeyond up to a tenth of the
    // radius, growing with |move|^4 beyond (to 10 % at 0.15).
    const double reach = move.norm() / (0.1 * radius);
    const double margin = 0.02 * std::max(1.0, reach * reach * reach * reach);
    if (reach <= 1.5 && modelDistance > (1.0 + margin) * options_.stopBeyond) {
      // Certainly beyond: the model's error is far below the margin (it grows like the margin,
      // about |move|^4 of the radius times the surface's fourth derivatives).
      endAt(p, moved);
      result_.model = model;
      result_.beyond = true;
      return true;
    }
    if (move.norm() <= options_.cubicFinishStep * radius) {
      // Within the model's reach of its origin: the answer, as a cubic finish there.
      endAt(p, moved);
      result_.model = model;
      result_.converged = true;
      return true;
    }
    wantThird_ = true;
    corrected_ = true;
    checkLast_ = true;
    lastStep_ = 0.0;
    stepEnd_ = ChartPoint{chartPoint_.vertex, p};
    current_ = surface_.atlas_.fromChart(*stepEnd_);
    return true;
  }

  /// The minimum of the distance to the nearby projection's cubic `model`, `move` from the
  /// model's origin (`moved`: the model there), from the Newton step at the nearby footpoint
  /// (the model's own first iterate there): to a last correction below 1e-3 of the radius
  /// (leaving about 1e-5 of it, below the model's own error there) where the iteration goes on
  /// from the result, 1e-7 where it is the answer. False when none was found well inside the
  /// chart (within 0.98 of its radius, at most half the radius from the origin).
  bool minimumOfNearbyModel(const Projection::CubicModel& model, const NewtonStep& newton,
                            Eigen::Vector2d& move, Jet3<2>& moved) const {
    const double radius = newton.radius;
    const Jet3<2> modelJet = fromDerivatives<2>(model.derivatives);
    move = chartPoint_.p - model.origin.p;
    if (newton.definite && !newton.clipped) move += newton.step;
    bool found = minimizeCubicModel(modelJet, model.derivatives.ddd, x_, 1e4 * radius, 8, move,
                                    moved, std::numeric_limits<double>::infinity());
    if (found && move.norm() <= options_.cubicFinishStep * radius) {
      found = minimizeCubicModel(modelJet, model.derivatives.ddd, x_, radius, 4, move, moved,
                                 std::numeric_limits<double>::infinity());
    }
    return found && (model.origin.p + move).norm() < 0.98 * radius && move.norm() <= 0.5 * radius;
  }

  /// The first step from a nearby projection (fromNearby) ends near the footpoint: the model
  /// there is expected to finish (or, beyond the band, to start the neighbours), and where it
  /// ends is kept for Projection::firstStepMiss. A Newton step that is not tiny takes the
  /// caller's second-order correction (in the same chart); such a step is checked by the next
  /// iterate's distance like any other, and being no plain Newton step it neither counts as tiny
  /// nor feeds the prediction of quadratic convergence.
  void prepareFirstStep(NewtonStep& newton, bool fromNearby) {
    wantThird_ = options_.cubicFinish && fromNearby;
    if (!fromNearby) return;
    if (!newton.clipped && (chartPoint_.p + newton.step).norm() < 0.99 * newton.radius) {
      firstEnd_ = ChartPoint{chartPoint_.vertex, chartPoint_.p + newton.step};
    }
    if (newton.definite && newton.length >= 1e-4 * newton.radius && options_.firstStepCorrection &&
        options_.firstStepCorrection->vertex == chartPoint_.vertex) {
      newton.step += options_.firstStepCorrection->p;
      if (newton.step.norm() > newton.maxStep) newton.step *= newton.maxStep / newton.step.norm();
      corrected_ = true;
    }
  }

  /// A tiny Newton step (positive definite Hessian) is taken as it is: there the quadratic model
  /// is exact to far below what comparing distances could resolve. Where Newton's quadratic
  /// convergence predicts that the next step would be below kTolerance of the radius, this step
  /// is the last: the answer is where it ends. Until a step has gone uphill, Newton steps up to a
  /// tenth of the radius are taken too, checked by the next iteration's distance. Other steps
  /// are halved until the distance falls.
  void takeStep(NewtonStep& newton) {
    const bool tiny = newton.definite && !corrected_ && newton.length < 1e-4 * newton.radius;
    if (tiny) {
      takeTinyStep(newton);
    } else if (!careful_ && newton.definite) {
      takeCheckedStep(newton);
    } else {
      takeHalvedStep(newton);
    }
  }

  void takeTinyStep(const NewtonStep& newton) {
    const double length = newton.length;
    const double radius = newton.radius;
    const double predicted = predictedNextStep(length, lastStep_, radius);
    finalStep_ = predicted <= kTolerance * radius;
    lastStep_ = length;
    checkLast_ = false;
    const Eigen::Vector2d p = chartPoint_.p + newton.step;
    if (finalStep_ && options_.extrapolateLastStep && length <= 1e-6 * radius &&
        p.norm() < 0.99 * radius) {
      endAt(p, quadraticTaylor(jet_, newton.step));
      result_.converged = true;
      return;
    }
    wantThird_ = options_.cubicFinish;
    current_ = stepTarget(newton.step, radius);
  }

  /// A Newton step taken unchecked: the next iterate's distance must be lower.
  void takeCheckedStep(const NewtonStep& newton) {
    if (options_.cubicFinish && !corrected_) {
      // Where quadratic convergence predicts a next step the cubic model can take.
      const double predicted = predictedNextStep(newton.length, lastStep_, newton.radius);
      wantThird_ = wantThird_ || predicted <= options_.cubicFinishStep * newton.radius;
    }
    lastStep_ = corrected_ ? 0.0 : newton.length;
    corrected_ = false;
    checkLast_ = true;
    current_ = stepTarget(newton.step, newton.radius);
  }

  /// A halved (or Gauss-Newton) step: a plain step, so a tiny one may end the iteration even
  /// after a corrected first step.
  void takeHalvedStep(NewtonStep& newton) {
    lastStep_ = 0.0;
    checkLast_ = false;
    corrected_ = false;
    for (int halving = 0; halving < 40; ++halving) {
      const FacePoint next = stepTarget(newton.step, newton.radius);
      if (0.5 * (surface_.position(next) - x_).squaredNorm() < newton.value) {
        current_ = next;
        return;
      }
      newton.step *= 0.5;
    }
    result_.converged = true;  // no step lowers the distance: a minimum to round-off
  }

  /// The face point at `move` from the iterate's chart point (kept within 0.99 of the radius);
  /// the chart point becomes stepEnd_.
  FacePoint stepTarget(const Eigen::Vector2d& move, double radius) {
    Eigen::Vector2d p = chartPoint_.p + move;
    if (p.norm() >= 0.99 * radius) p *= 0.99 * radius / p.norm();
    stepEnd_ = ChartPoint{chartPoint_.vertex, p};
    return surface_.atlas_.fromChart(*stepEnd_);
  }

  /// Ends the projection at chart point p of chartPoint_'s vertex with the jet `there`: its face
  /// point, the corner of that vertex and the jet.
  __attribute__((always_inline)) void endAt(const Eigen::Vector2d& p, const Jet3<2>& there) {
    current_ = surface_.atlas_.fromChart({chartPoint_.vertex, p});
    for (int c = 0; c < 3; ++c) {
      if (mesh_.from(3 * current_.face + static_cast<Index>(c)) == chartPoint_.vertex) center_ = c;
    }
    jet_ = there;
    chartPoint_.p = p;
  }

  /// Keeps the cubic model at the current iterate (jet_ and third_) in the result, built in place.
  __attribute__((always_inline)) void keepModel() {
    Projection::CubicModel& model = result_.model.emplace();
    model.origin = chartPoint_;
    model.derivatives.position = jet_.v;
    for (int i = 0; i < 2; ++i) model.derivatives.d[i] = jet_.d[i];
    for (int i = 0; i < 3; ++i) model.derivatives.dd[i] = jet_.h[i];
    for (int i = 0; i < 4; ++i) model.derivatives.ddd[i] = third_[i];
  }

  /// Evaluates where an unfinished iteration ended and writes the result.
  void finish() {
    if (!stopped()) {
      center_ = nearestCorner(current_.bary);
      jet_ = Evaluator<2>{surface_}.chart(current_, center_, &chartPoint_.p);
      ++result_.iterations;
    }
    if (result_.converged && firstEnd_ && firstEnd_->vertex == chartPoint_.vertex) {
      result_.firstStepMiss = ChartPoint{chartPoint_.vertex, chartPoint_.p - firstEnd_->p};
    }
    result_.point = current_;
    result_.chartPoint = chartPoint_.p;
    result_.position = jet_.v;
    result_.distance = (jet_.v - x_).norm();
    result_.derivatives = toDerivatives(jet_);
    result_.chartCorner = center_;
    if (result_.beyond) {
      result_.geometry = SmoothPoint{};
      result_.geometry.position = jet_.v;  // stopped: no differential geometry
    } else {
      result_.geometry = surfaceGeometry(result_.derivatives);
    }
  }

  const PseudoManifold& surface_;
  const HalfEdgeMesh& mesh_;
  const Eigen::Vector3d& x_;
  const Projection* nearby_;  ///< the projection that ended at the start, if given
  const SmoothProjectionOptions& options_;
  Projection& result_;

  FacePoint current_;   ///< the iterate
  FacePoint previous_;  ///< the iterate to go back to when an unchecked step goes uphill
  double previousValue_ = std::numeric_limits<double>::infinity();  ///< |X - x|^2 / 2 there
  bool careful_ = false;    ///< set once an unchecked step went uphill
  bool checkLast_ = false;  ///< the last step was taken unchecked and must lower the distance
  bool finalStep_ = false;  ///< the last step was predicted to converge: evaluate there and stop
  double lastStep_ =
      0.0;       ///< length of the last Newton step taken in the quadratic regime, 0: none
  bool known_;   ///< the derivatives at current_ are the nearby projection's
  Jet3<2> jet_;  ///< the derivatives at current_
  int center_;   ///< the corner of current_'s face whose chart jet_ is taken in
  ChartPoint chartPoint_;  ///< current_ in that chart
  /// Where the first Newton step from nearby_ ended (for Projection::firstStepMiss).
  std::optional<ChartPoint> firstEnd_;
  bool corrected_ = false;  ///< the first step included options_.firstStepCorrection
  /// Where the last step taken ended, in the chart it was taken in (current_ is its face point).
  std::optional<ChartPoint> stepEnd_;
  /// Evaluate current_ with third derivatives (options_.cubicFinish: the step there is expected
  /// to end near the footpoint); third_ holds them when haveThird_.
  bool wantThird_ = false;
  bool haveThird_ = false;
  Eigen::Vector3d third_[4];
};

void PseudoManifold::projectFrom(const Eigen::Vector3d& x, const FacePoint& start,
                                 const Projection* nearby, const SmoothProjectionOptions& options,
                                 Projection& result) const {
  ProjectionRun(*this, x, start, nearby, options, result).run();
}

std::size_t PseudoManifold::memoryBytes() const {
  std::size_t bytes =
      controls_.capacity() * sizeof(double) + controlOffset_.capacity() * sizeof(std::size_t);
  for (const auto& fit : fits_) {
    if (!fit) continue;
    bytes += static_cast<std::size_t>(fit->pseudoInverse.size()) * sizeof(double) +
             fit->canonical.capacity() * sizeof(Eigen::Vector2d);
  }
  return bytes;
}

}  // namespace d2vdb
