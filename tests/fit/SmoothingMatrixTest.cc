// The smoothing Gram matrices and the sensor basis against direct evaluation of the curve.
#include "d2vdb/fit/detail/SmoothingMatrix.h"

#include <gtest/gtest.h>

#include <cmath>

#include "FitTestSupport.h"
#include "d2vdb/fit/detail/SensorBasis.h"

namespace d2vdb::detail {
namespace {

BSplineCurve wavyCurve(bool closed) {
  std::vector<Eigen::Vector3d> controls;
  for (int i = 0; i < 9; ++i) {
    controls.emplace_back(std::cos(0.7 * i) + 0.1 * i, std::sin(1.3 * i), 0.2 * i * i);
  }
  return closed ? BSplineCurve::closed(3, controls, 3, {2.0, 5.0})
                : BSplineCurve::clamped(3, controls, 3, {2.0, 5.0});
}

// int_0^1 |x^(r)(u)|^2 du by the composite midpoint rule on the curve's own derivatives.
double energyByQuadrature(const BSplineCurve& curve, int order) {
  const ParameterInterval domain = curve.domain();
  const int steps = 200000;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double t = domain.at((i + 0.5) / steps);
    sum += std::pow(domain.length(), 2 * order) * curve.derivative(t, order).squaredNorm();
  }
  return sum / steps;
}

TEST(SmoothingMatrix, GramEnergyEqualsTheIntegralOfTheSquaredDerivative) {
  for (const bool closed : {false, true}) {
    const BSplineCurve curve = wavyCurve(closed);
    for (const int order : {1, 2}) {
      const Eigen::SparseMatrix<double> gram = derivativeGramMatrix(curve, order);
      double energy = 0.0;
      for (int a = 0; a < 3; ++a) {
        Eigen::VectorXd x(curve.controlPointCount());
        for (int i = 0; i < curve.controlPointCount(); ++i) {
          x[i] = curve.controlPoints()[static_cast<std::size_t>(i)][a];
        }
        energy += x.dot(gram * x);
      }
      EXPECT_NEAR(energy, energyByQuadrature(curve, order), 1e-6 * energy)
          << "closed " << closed << " order " << order;
    }
  }
}

TEST(SensorBasis, PositionsEqualCurveEvaluation) {
  for (const bool closed : {false, true}) {
    const BSplineCurve curve = wavyCurve(closed);
    const SensorBasis basis(curve, uniformSensorParameters(curve, 5));
    EXPECT_EQ(basis.sensorCount(),
              5 * static_cast<int>(curve.knots().breakpoints().size() - 1) + (closed ? 0 : 2));
    const std::vector<Eigen::Vector3d> positions = basis.positions(curve.controlPoints());
    for (int k = 0; k < basis.sensorCount(); ++k) {
      EXPECT_LT(
          (positions[static_cast<std::size_t>(k)] - curve.evaluate(basis.parameter(k))).norm(),
          1e-12);
    }
  }
}

TEST(SmoothingMatrix, GaussLegendreIsExactForPolynomials) {
  std::vector<double> nodes;
  std::vector<double> weights;
  for (int n = 1; n <= 8; ++n) {
    gaussLegendre(n, nodes, weights);
    for (int degree = 0; degree <= 2 * n - 1; ++degree) {
      double sum = 0.0;
      for (int i = 0; i < n; ++i)
        sum += weights[static_cast<std::size_t>(i)] *
               std::pow(nodes[static_cast<std::size_t>(i)], degree);
      EXPECT_NEAR(sum, 1.0 / (degree + 1), 1e-14) << n << " " << degree;
    }
  }
}

}  // namespace
}  // namespace d2vdb::detail
