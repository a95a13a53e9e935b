#include "d2vdb/spline/BezierPatch.h"

#include <array>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

// de Casteljau on `count` points at t (in place); returns the curve point.
Eigen::Vector3d deCasteljau(std::array<Eigen::Vector3d, kMaxSplineDegree + 1>& points, int count,
                            double t) {
  for (int level = 1; level < count; ++level) {
    for (int i = 0; i + level < count; ++i) {
      points[static_cast<std::size_t>(i)] = (1.0 - t) * points[static_cast<std::size_t>(i)] +
                                            t * points[static_cast<std::size_t>(i) + 1];
    }
  }
  return points[0];
}

}  // namespace

Eigen::Vector3d BezierPatch::evaluate(double s, double t) const {
  std::array<Eigen::Vector3d, kMaxSplineDegree + 1> row;
  std::array<Eigen::Vector3d, kMaxSplineDegree + 1> column;
  for (int a = 0; a <= degreeU; ++a) {
    for (int b = 0; b <= degreeV; ++b) {
      row[static_cast<std::size_t>(b)] =
          controlPoints[static_cast<std::size_t>(a * (degreeV + 1) + b)];
    }
    column[static_cast<std::size_t>(a)] = deCasteljau(row, degreeV + 1, t);
  }
  return deCasteljau(column, degreeU + 1, s);
}

Eigen::MatrixXd bezierExtractionMatrix(const KnotVector& knots, int span) {
  const int p = knots.degree();
  if (span < p || span >= knots.basisFunctionCount() || !(knots[span] < knots[span + 1])) {
    throw InputError("Bezier extraction: " + std::to_string(span) +
                     " is not a non-empty knot span index");
  }
  const double a = knots[span];
  const double b = knots[span + 1];
  Eigen::MatrixXd matrix(p + 1, p + 1);
  for (int c = 0; c <= p; ++c) {
    // de Boor's recurrence for the blossom with p - c arguments a and c arguments b, run on the
    // unit coefficient vectors, so that row c holds the weights of d_0..d_p.
    Eigen::MatrixXd d = Eigen::MatrixXd::Identity(p + 1, p + 1);  // column j = d_j
    for (int r = 1; r <= p; ++r) {
      const double x = r <= p - c ? a : b;
      for (int j = p; j >= r; --j) {
        const double left = knots[span - p + j];
        const double alpha = (x - left) / (knots[span + j - r + 1] - left);
        d.col(j) = (1.0 - alpha) * d.col(j - 1) + alpha * d.col(j);
      }
    }
    matrix.row(c) = d.col(p).transpose();
  }
  return matrix;
}

std::vector<BezierPatch> toBezierPatches(const BSplineSurface& surface) {
  const KnotVector& knotsU = surface.knotsU();
  const KnotVector& knotsV = surface.knotsV();
  const int p = surface.degreeU();
  const int q = surface.degreeV();
  std::vector<BezierPatch> patches;
  for (int spanU = p; spanU < knotsU.basisFunctionCount(); ++spanU) {
    if (!(knotsU[spanU] < knotsU[spanU + 1])) continue;
    const Eigen::MatrixXd mu = bezierExtractionMatrix(knotsU, spanU);
    for (int spanV = q; spanV < knotsV.basisFunctionCount(); ++spanV) {
      if (!(knotsV[spanV] < knotsV[spanV + 1])) continue;
      const Eigen::MatrixXd mv = bezierExtractionMatrix(knotsV, spanV);
      BezierPatch patch;
      patch.degreeU = p;
      patch.degreeV = q;
      patch.spanU = spanU;
      patch.spanV = spanV;
      patch.intervalU = {knotsU[spanU], knotsU[spanU + 1]};
      patch.intervalV = {knotsV[spanV], knotsV[spanV + 1]};
      patch.controlPoints.assign(static_cast<std::size_t>((p + 1) * (q + 1)),
                                 Eigen::Vector3d::Zero());
      for (int i = 0; i <= p; ++i) {
        for (int j = 0; j <= q; ++j) {
          const Eigen::Vector3d& d = surface.controlPoints()[static_cast<std::size_t>(
              surface.controlPointIndex(spanU - p + i, spanV - q + j))];
          for (int a = 0; a <= p; ++a) {
            const double wa = mu(a, i);
            if (wa == 0.0) continue;
            for (int b = 0; b <= q; ++b) {
              patch.controlPoints[static_cast<std::size_t>(a * (q + 1) + b)] += (wa * mv(b, j)) * d;
            }
          }
        }
      }
      patches.push_back(std::move(patch));
    }
  }
  return patches;
}

}  // namespace d2vdb
