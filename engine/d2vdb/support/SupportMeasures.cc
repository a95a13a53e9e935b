#include "d2vdb/support/SupportMeasures.h"

#include "d2vdb/support/SphereQuadrature.h"

namespace d2vdb {

SupportMeasures supportMeasures(const SupportFunction& h) {
  const SphereQuadrature rule = sphereQuadrature(3 * h.degree() + 4);
  const std::vector<SupportPoint> points = h.evaluate(rule.nodes);
  SupportMeasures measures;
  for (std::size_t q = 0; q < points.size(); ++q) {
    const double w = rule.weights[q];
    const double det = points[q].determinant();
    measures.area += w * det;
    measures.volume += w * points[q].value * det / 3.0;
    measures.meanCurvatureIntegral += w * points[q].value;
  }
  return measures;
}

}  // namespace d2vdb
