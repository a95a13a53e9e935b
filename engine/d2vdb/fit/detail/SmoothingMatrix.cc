#include "d2vdb/fit/detail/SmoothingMatrix.h"

#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/GaussLegendre.h"
#include "d2vdb/spline/BasisFunctions.h"

namespace d2vdb::detail {

void gaussLegendre(int count, std::vector<double>& nodes, std::vector<double>& weights) {
  if (count < 1 || count > 64) {
    throw InputError("Gauss-Legendre rule needs 1..64 points, got " + std::to_string(count));
  }
  const GaussLegendreRule rule = gaussLegendreRule(count);
  nodes.resize(rule.nodes.size());
  weights.resize(rule.weights.size());
  // Map from [-1, 1] to [0, 1].
  for (std::size_t i = 0; i < rule.nodes.size(); ++i) {
    nodes[i] = 0.5 * (1.0 - rule.nodes[i]);
    weights[i] = 0.5 * rule.weights[i];
  }
}

Eigen::SparseMatrix<double> derivativeGramMatrix(const BSplineCurve& curve, int derivativeOrder) {
  const int p = curve.degree();
  if (derivativeOrder < 1 || derivativeOrder > p) {
    throw InputError("smoothing derivative order must be 1.." + std::to_string(p) +
                     " for a degree-" + std::to_string(p) + " curve, got " +
                     std::to_string(derivativeOrder));
  }
  const KnotVector& knots = curve.knots();
  const double length = curve.domain().length();
  const double scale = std::pow(length, 2.0 * derivativeOrder - 1.0);
  std::vector<double> nodes;
  std::vector<double> weights;
  gaussLegendre(p + 1, nodes, weights);
  const int n = curve.controlPointCount();
  std::vector<Eigen::Triplet<double>> triplets;
  const std::vector<double> breaks = knots.breakpoints();
  for (std::size_t s = 0; s + 1 < breaks.size(); ++s) {
    const ParameterInterval span{breaks[s], breaks[s + 1]};
    const int spanIndex = knots.findSpan(span.at(0.5));
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(p + 1, p + 1);
    for (std::size_t q = 0; q < nodes.size(); ++q) {
      const double t = span.at(nodes[q]);
      const BasisDerivatives d = basisDerivatives(knots, spanIndex, t, derivativeOrder);
      const Eigen::VectorXd row = d.row(derivativeOrder).transpose();
      block += (weights[q] * span.length()) * row * row.transpose();
    }
    for (int a = 0; a <= p; ++a) {
      for (int b = 0; b <= p; ++b) {
        triplets.emplace_back(curve.controlPointIndex(spanIndex - p + a),
                              curve.controlPointIndex(spanIndex - p + b), scale * block(a, b));
      }
    }
  }
  Eigen::SparseMatrix<double> gram(n, n);
  gram.setFromTriplets(triplets.begin(), triplets.end());
  return gram;
}

}  // namespace d2vdb::detail
