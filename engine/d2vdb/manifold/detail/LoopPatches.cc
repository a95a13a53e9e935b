#include "d2vdb/manifold/detail/LoopPatches.h"

#include <Eigen/LU>

#include <cmath>
#include <vector>

#include "d2vdb/manifold/detail/ChartMath.h"

namespace d2vdb::detail {
namespace {

/// Values on the integer points (i, j), |i|, |j| <= radius, of a regular triangular lattice
/// (directions (1, 0), (0, 1), (-1, 1) and their opposites are the six neighbours).
class LatticeValues {
 public:
  explicit LatticeValues(int radius)
      : radius_(radius),
        values_(static_cast<std::size_t>((2 * radius + 1) * (2 * radius + 1)), 0.0) {}

  int radius() const { return radius_; }
  bool contains(int i, int j) const { return std::abs(i) <= radius_ && std::abs(j) <= radius_; }
  double& at(int i, int j) { return values_[index(i, j)]; }
  double at(int i, int j) const { return values_[index(i, j)]; }

  /// Sum of the six lattice neighbours of (i, j) (all must be inside).
  double neighborSum(int i, int j) const {
    return at(i + 1, j) + at(i - 1, j) + at(i, j + 1) + at(i, j - 1) + at(i + 1, j - 1) +
           at(i - 1, j + 1);
  }

  /// One step of Loop subdivision with the regular rules; the finer lattice keeps the points whose
  /// stencils lie inside this one.
  LatticeValues subdivided() const {
    const int inner = radius_ - 1;  // points of this lattice whose neighbours are all inside
    LatticeValues finer(2 * inner);
    const auto inside = [&](int i, int j) { return std::abs(i) <= inner && std::abs(j) <= inner; };
    for (int fi = -finer.radius_; fi <= finer.radius_; ++fi) {
      for (int fj = -finer.radius_; fj <= finer.radius_; ++fj) {
        const int i = floorHalf(fi);
        const int j = floorHalf(fj);
        const bool oddI = fi - 2 * i == 1;
        const bool oddJ = fj - 2 * j == 1;
        double value = 0.0;
        if (!oddI && !oddJ) {
          if (!inside(i, j)) continue;
          value = 10.0 / 16.0 * at(i, j) + 1.0 / 16.0 * neighborSum(i, j);
        } else if (oddI && !oddJ) {  // edge (i, j)-(i+1, j), opposite (i, j+1) and (i+1, j-1)
          if (!inside(i, j) || !inside(i + 1, j)) continue;
          value =
              3.0 / 8.0 * (at(i, j) + at(i + 1, j)) + 1.0 / 8.0 * (at(i, j + 1) + at(i + 1, j - 1));
        } else if (!oddI && oddJ) {  // edge (i, j)-(i, j+1), opposite (i+1, j) and (i-1, j+1)
          if (!inside(i, j) || !inside(i, j + 1)) continue;
          value =
              3.0 / 8.0 * (at(i, j) + at(i, j + 1)) + 1.0 / 8.0 * (at(i + 1, j) + at(i - 1, j + 1));
        } else {  // edge (i+1, j)-(i, j+1), opposite (i, j) and (i+1, j+1)
          if (!inside(i + 1, j) || !inside(i, j + 1)) continue;
          value =
              3.0 / 8.0 * (at(i + 1, j) + at(i, j + 1)) + 1.0 / 8.0 * (at(i, j) + at(i + 1, j + 1));
        }
        finer.at(fi, fj) = value;
      }
    }
    return finer;
  }

 private:
  static int floorHalf(int x) { return x >= 0 ? x / 2 : -((-x + 1) / 2); }
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>((i + radius_) * (2 * radius_ + 1) + (j + radius_));
  }

  int radius_;
  std::vector<double> values_;
};

Eigen::Matrix<double, 15, kRegularControlCount> deriveRegularPatchMatrix() {
  // Quartic Bernstein basis at the 15 points (v, w) = (i/4, j/4), i + j <= 4.
  Eigen::Matrix<double, 15, 15> basis;
  std::array<std::array<int, 2>, 15> points{};
  int row = 0;
  for (int i = 0; i <= 4; ++i) {
    for (int j = 0; j <= 4 - i; ++j) points[row++] = {i, j};
  }
  const double factorial[5] = {1, 1, 2, 6, 24};
  for (int p = 0; p < 15; ++p) {
    const double v = points[p][0] / 4.0;
    const double w = points[p][1] / 4.0;
    const double u = 1.0 - v - w;
    for (int j = 0; j <= 4; ++j) {
      for (int k = 0; k <= 4 - j; ++k) {
        const int i = 4 - j - k;
        basis(p, triangleIndex(4, j, k)) = 24.0 / (factorial[i] * factorial[j] * factorial[k]) *
                                           std::pow(u, i) * std::pow(v, j) * std::pow(w, k);
      }
    }
  }
  const Eigen::FullPivLU<Eigen::Matrix<double, 15, 15>> lu(basis);
  Eigen::Matrix<double, 15, kRegularControlCount> matrix;
  for (int c = 0; c < kRegularControlCount; ++c) {
    LatticeValues level0(5);
    level0.at(kRegularLattice[c][0], kRegularLattice[c][1]) = 1.0;
    const LatticeValues level2 = level0.subdivided().subdivided();
    Eigen::Matrix<double, 15, 1> limits;
    for (int p = 0; p < 15; ++p) {
      const int i = points[p][0];
      const int j = points[p][1];
      limits[p] = 0.5 * level2.at(i, j) + level2.neighborSum(i, j) / 12.0;
    }
    matrix.col(c) = lu.solve(limits);
  }
  return matrix;
}

}  // namespace

double loopBeta(int valence) {
  const double a = 3.0 / 8.0 + 0.25 * std::cos(2.0 * kPi / valence);
  return (5.0 / 8.0 - a * a) / valence;
}

const Eigen::Matrix<double, 15, kRegularControlCount>& regularPatchMatrix() {
  static const Eigen::Matrix<double, 15, kRegularControlCount> matrix = deriveRegularPatchMatrix();
  return matrix;
}

std::array<Eigen::Vector3d, 15> regularNet(const std::array<Eigen::Vector3d, 12>& controls) {
  static const Eigen::Matrix<double, 15, kRegularControlCount> m = regularPatchMatrix();
  Eigen::Matrix<double, kRegularControlCount, 3> points;
  for (int c = 0; c < kRegularControlCount; ++c) points.row(c) = controls[c].transpose();
  const Eigen::Matrix<double, 15, 3> product = m * points;
  std::array<Eigen::Vector3d, 15> net;
  for (int r = 0; r < 15; ++r) net[r] = product.row(r).transpose();
  return net;
}

ExtraordinaryTemplate::ExtraordinaryTemplate(int valenceN) : valence(valenceN) {
  const int n = valence;
  const int k = n + 6;
  // Template indices.
  const int c = 0;
  const auto nb = [n](int i) { return 1 + ((i - 1) % n + n) % n; };  // n_i, i taken mod N (1-based)
  const int b = n + 1;
  const int a = n + 2;
  const int m = n + 3;
  const int d = n + 4;
  const int e = n + 5;
  step = Eigen::MatrixXd::Zero(k, k);
  const double beta = loopBeta(n);
  step(c, c) = 1.0 - n * beta;
  for (int i = 1; i <= n; ++i) step(c, nb(i)) = beta;
  const auto edge = [](Eigen::MatrixXd& rows, int row, int p, int q, int r, int s) {
    rows(row, p) += 3.0 / 8.0;
    rows(row, q) += 3.0 / 8.0;
    rows(row, r) += 1.0 / 8.0;
    rows(row, s) += 1.0 / 8.0;
  };
  for (int i = 1; i <= n; ++i) edge(step, nb(i), c, nb(i), nb(i - 1), nb(i + 1));
  edge(step, b, nb(n), nb(1), c, b);  // edge n_N - n1, opposite c and b
  // Vertex point of n1 (valence 6): ring n2, c, nN, b, a, m.
  step(a, nb(1)) += 10.0 / 16.0;
  for (const int q : {nb(2), c, nb(n), b, a, m}) step(a, q) += 1.0 / 16.0;
  edge(step, m, nb(1), nb(2), c, m);  // edge n1 - n2, opposite c and m
  // Vertex point of n2 (valence 6): ring c, n1, m, d, e, n3.
  step(d, nb(2)) += 10.0 / 16.0;
  for (const int q : {c, nb(1), m, d, e, nb(3)}) step(d, q) += 1.0 / 16.0;
  edge(step, e, nb(2), nb(3), c, e);  // edge n2 - n3, opposite c and e

  extra = Eigen::MatrixXd::Zero(6, k);
  edge(extra, 0, nb(1), b, nb(n), a);  // n1 - b: faces (n1, nN, b), (n1, b, a)
  edge(extra, 1, nb(1), a, b, m);      // n1 - a: faces (n1, b, a), (n1, a, m)
  edge(extra, 2, nb(1), m, a, nb(2));  // n1 - m: faces (n1, a, m), (n1, m, n2)
  edge(extra, 3, nb(2), m, nb(1), d);  // n2 - m: faces (n2, n1, m), (n2, m, d)
  edge(extra, 4, nb(2), d, m, e);      // n2 - d: faces (n2, m, d), (n2, d, e)
  edge(extra, 5, nb(2), e, d, nb(3));  // n2 - e: faces (n2, d, e), (n2, e, n3)

  // Finer level, lattice positions around the sub-triangle (c', n1', n2') = (0,0), (1,0), (0,1):
  // n_N' (1,-1), n3' (-1,1), b' (2,-1), a' (2,0), m' (1,1), d' (0,2), e' (-1,2), and the extras
  // (3,-1), (3,0), (2,1), (1,2), (0,3), (-1,3).
  const int n1 = nb(1);
  const int n2 = nb(2);
  const int n3 = nb(3);
  const int nN = nb(n);
  const int x0 = k;                                                           // e(n1, b)
  subPatch[0] = {n1, a, m, c, nN, b, n2, x0 + 1, x0 + 2, x0, x0 + 3, d};      // T1 at n1
  subPatch[1] = {m, n2, n1, x0 + 2, x0 + 3, d, a, n3, c, e, nN, b};           // T2 centre
  subPatch[2] = {n2, m, d, n3, c, n1, e, x0 + 2, x0 + 3, a, x0 + 4, x0 + 5};  // T3 at n2

  Eigen::MatrixXd stacked(k + 6, k);
  stacked << step, extra;
  for (int t = 0; t < 3; ++t) {
    Eigen::MatrixXd selected(12, k);
    for (int j = 0; j < 12; ++j) selected.row(j) = stacked.row(subPatch[t][j]);
    subPatchNet[t] = regularPatchMatrix() * selected;
  }

  const double chi = 1.0 / (3.0 / (8.0 * beta) + n);
  limitCenter = 1.0 - n * chi;
  limitNeighbor = chi;
}

}  // namespace d2vdb::detail
