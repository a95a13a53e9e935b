// Thin-plate and membrane matrices of B-spline surfaces against closed-form energies of a
// quadratic graph (reproduced exactly by a clamped bicubic) and against brute-force quadrature on
// closed (periodic) surfaces.
#include "d2vdb/fit/detail/ThinPlateMatrix.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "d2vdb/fit/detail/SmoothingMatrix.h"
#include "d2vdb/spline/BasisFunctions.h"

namespace d2vdb::detail {
namespace {

/// sum_a P_a^T M P_a.
double energy(const Eigen::SparseMatrix<double>& matrix,
              const std::vector<Eigen::Vector3d>& points) {
  double total = 0.0;
  for (int a = 0; a < 3; ++a) {
    Eigen::VectorXd coordinate(static_cast<Eigen::Index>(points.size()));
    for (std::size_t i = 0; i < points.size(); ++i)
      coordinate[static_cast<Eigen::Index>(i)] = points[i][a];
    total += coordinate.dot(matrix * coordinate);
  }
  return total;
}

/// The collocation matrix N_j(xi_i) at the Greville abscissae of an open knot vector.
Eigen::MatrixXd grevilleCollocation(const KnotVector& knots, std::vector<double>& abscissae) {
  const int n = knots.basisFunctionCount();
  const int p = knots.degree();
  Eigen::MatrixXd matrix = Eigen::MatrixXd::Zero(n, n);
  abscissae.clear();
  for (int i = 0; i < n; ++i) {
    double xi = 0.0;
    for (int r = 1; r <= p; ++r) xi += knots[i + r];
    xi /= p;
    abscissae.push_back(xi);
    const int span = knots.findSpan(xi);
    const BasisValues values = basisValues(knots, span, xi);
    for (int j = 0; j <= p; ++j) matrix(i, span - p + j) = values[j];
  }
  return matrix;
}

TEST(ThinPlateMatrix, QuadraticGraphHasItsClosedFormEnergies) {
  // S(u, v) = (s, t, a s^2 + b s t + c t^2) with s, t the parameters normalised to [0, 1].
  const double a = 0.7, b = -1.3, c = 0.4;
  const ParameterInterval domainU{2.0, 5.0}, domainV{-1.0, 1.0};
  const KnotVector knotsU = KnotVector::clamped(3, 7, domainU);
  const KnotVector knotsV = KnotVector::clamped(3, 6, domainV);
  std::vector<double> us, vs;
  const Eigen::MatrixXd cu = grevilleCollocation(knotsU, us);
  const Eigen::MatrixXd cv = grevilleCollocation(knotsV, vs);
  Eigen::MatrixXd values[3];
  for (int axis = 0; axis < 3; ++axis) values[axis].resize(7, 6);
  for (int i = 0; i < 7; ++i) {
    for (int j = 0; j < 6; ++j) {
      const double s = (us[static_cast<std::size_t>(i)] - 2.0) / 3.0;
      const double t = (vs[static_cast<std::size_t>(j)] + 1.0) / 2.0;
      values[0](i, j) = s;
      values[1](i, j) = t;
      values[2](i, j) = a * s * s + b * s * t + c * t * t;
    }
  }
  std::vector<Eigen::Vector3d> points(42);
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::MatrixXd coefficients =
        cu.fullPivLu().solve(cv.fullPivLu().solve(values[axis].transpose()).transpose());
    for (int i = 0; i < 7; ++i) {
      for (int j = 0; j < 6; ++j)
        points[static_cast<std::size_t>(i * 6 + j)][axis] = coefficients(i, j);
    }
  }
  const BSplineSurface surface(knotsU, knotsV, points);
  ASSERT_NEAR(surface.evaluate(3.5, 0.0).z(), a * 0.25 + b * 0.25 + c * 0.25, 1e-13);
  EXPECT_NEAR(energy(thinPlateMatrix(surface), points), 4 * a * a + 2 * b * b + 4 * c * c, 1e-11);
  EXPECT_NEAR(energy(membraneMatrix(surface), points),
              2.0 + 4 * a * a / 3 + a * b + 2 * b * b / 3 + b * c + 4 * c * c / 3, 1e-11);
  // Affine maps of the parameters are in the thin-plate null space.
  std::vector<Eigen::Vector3d> flat = points;
  for (Eigen::Vector3d& point : flat) point.z() = 0.3 * point.x() - 2.0 * point.y() + 1.0;
  EXPECT_NEAR(energy(thinPlateMatrix(surface), flat), 0.0, 1e-11);
}

/// Energies by brute-force quadrature: 12 x 12 Gauss points per knot cell on the surface's own
/// derivatives.
void bruteEnergies(const BSplineSurface& surface, double& thinPlate, double& membrane) {
  std::vector<double> nodes, weights;
  gaussLegendre(12, nodes, weights);
  const std::vector<double> breaksU = surface.knotsU().breakpoints();
  const std::vector<double> breaksV = surface.knotsV().breakpoints();
  const double lu = surface.domainU().length(), lv = surface.domainV().length();
  thinPlate = membrane = 0.0;
  for (std::size_t su = 0; su + 1 < breaksU.size(); ++su) {
    for (std::size_t sv = 0; sv + 1 < breaksV.size(); ++sv) {
      const ParameterInterval iu{breaksU[su], breaksU[su + 1]}, iv{breaksV[sv], breaksV[sv + 1]};
      for (std::size_t i = 0; i < nodes.size(); ++i) {
        for (std::size_t j = 0; j < nodes.size(); ++j) {
          const SurfaceDerivatives d = surface.derivatives(iu.at(nodes[i]), iv.at(nodes[j]));
          const double w = weights[i] * weights[j] * iu.length() * iv.length() / (lu * lv);
          thinPlate += w * (std::pow(lu, 4) * d.duu.squaredNorm() +
                            2 * lu * lu * lv * lv * d.duv.squaredNorm() +
                            std::pow(lv, 4) * d.dvv.squaredNorm());
          membrane += w * (lu * lu * d.du.squaredNorm() + lv * lv * d.dv.squaredNorm());
        }
      }
    }
  }
}

TEST(ThinPlateMatrix, ClosedSurfacesMatchBruteForceQuadrature) {
  std::mt19937 engine(12);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const auto& [p, q, closedU, closedV] :
       {std::tuple{3, 3, true, true}, std::tuple{2, 3, true, false},
        std::tuple{1, 3, false, true}}) {
    const int nu = 7, nv = 6;
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < nu * nv; ++i)
      points.emplace_back(uniform(engine), uniform(engine), uniform(engine));
    const BSplineSurface surface(
        closedU ? KnotVector::periodic(p, nu, {0.0, 2.0}) : KnotVector::clamped(p, nu, {0.0, 2.0}),
        closedV ? KnotVector::periodic(q, nv, {1.0, 1.5}) : KnotVector::clamped(q, nv, {1.0, 1.5}),
        points, closedU, closedV);
    double thinPlate = 0.0, membrane = 0.0;
    bruteEnergies(surface, thinPlate, membrane);
    EXPECT_NEAR(energy(thinPlateMatrix(surface), points), thinPlate, 1e-10 * thinPlate);
    EXPECT_NEAR(energy(membraneMatrix(surface), points), membrane, 1e-10 * membrane);
    const Eigen::SparseMatrix<double> matrix = thinPlateMatrix(surface);
    EXPECT_LT(Eigen::MatrixXd(matrix - Eigen::SparseMatrix<double>(matrix.transpose())).norm(),
              1e-12 * Eigen::MatrixXd(matrix).norm());
  }
}

}  // namespace
}  // namespace d2vdb::detail
