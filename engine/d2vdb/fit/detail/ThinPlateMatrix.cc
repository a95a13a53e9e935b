#include "d2vdb/fit/detail/ThinPlateMatrix.h"

#include <vector>

#include "d2vdb/fit/detail/SmoothingMatrix.h"
#include "d2vdb/spline/BasisFunctions.h"

namespace d2vdb::detail {
namespace {

enum class Energy { ThinPlate, Membrane };

Eigen::SparseMatrix<double> energyMatrix(const BSplineSurface& surface, Energy energy) {
  const int p = surface.degreeU();
  const int q = surface.degreeV();
  const KnotVector& knotsU = surface.knotsU();
  const KnotVector& knotsV = surface.knotsV();
  const double lengthU = surface.domainU().length();
  const double lengthV = surface.domainV().length();
  // d/ds = L_u d/du, ds = du / L_u: the weights of the parameter-space integrand.
  const double area = 1.0 / (lengthU * lengthV);
  const double wuu = lengthU * lengthU * lengthU * lengthU * area;
  const double wuv = 2.0 * lengthU * lengthU * lengthV * lengthV * area;
  const double wvv = lengthV * lengthV * lengthV * lengthV * area;
  const double wu = lengthU * lengthU * area;
  const double wv = lengthV * lengthV * area;
  std::vector<double> nodesU, weightsU, nodesV, weightsV;
  gaussLegendre(p + 1, nodesU, weightsU);
  gaussLegendre(q + 1, nodesV, weightsV);
  const int order = (p + 1) * (q + 1);
  const std::vector<double> breaksU = knotsU.breakpoints();
  const std::vector<double> breaksV = knotsV.breakpoints();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve((breaksU.size() - 1) * (breaksV.size() - 1) * static_cast<std::size_t>(order) *
                   static_cast<std::size_t>(order));
  Eigen::VectorXd du(order), dv(order), duu(order), duv(order), dvv(order);
  for (std::size_t su = 0; su + 1 < breaksU.size(); ++su) {
    const ParameterInterval spanU{breaksU[su], breaksU[su + 1]};
    const int indexU = knotsU.findSpan(spanU.at(0.5));
    for (std::size_t sv = 0; sv + 1 < breaksV.size(); ++sv) {
      const ParameterInterval spanV{breaksV[sv], breaksV[sv + 1]};
      const int indexV = knotsV.findSpan(spanV.at(0.5));
      Eigen::MatrixXd block = Eigen::MatrixXd::Zero(order, order);
      for (std::size_t i = 0; i < nodesU.size(); ++i) {
        const BasisDerivatives bu = basisDerivatives(knotsU, indexU, spanU.at(nodesU[i]), 2);
        for (std::size_t j = 0; j < nodesV.size(); ++j) {
          const BasisDerivatives bv = basisDerivatives(knotsV, indexV, spanV.at(nodesV[j]), 2);
          const double weight = weightsU[i] * spanU.length() * weightsV[j] * spanV.length();
          for (int a = 0; a <= p; ++a) {
            for (int b = 0; b <= q; ++b) {
              const int k = a * (q + 1) + b;
              du[k] = bu(1, a) * bv(0, b);
              dv[k] = bu(0, a) * bv(1, b);
              duu[k] = bu(2, a) * bv(0, b);
              duv[k] = bu(1, a) * bv(1, b);
              dvv[k] = bu(0, a) * bv(2, b);
            }
          }
          if (energy == Energy::ThinPlate) {
            block.noalias() += (weight * wuu) * duu * duu.transpose();
            block.noalias() += (weight * wuv) * duv * duv.transpose();
            block.noalias() += (weight * wvv) * dvv * dvv.transpose();
          } else {
            block.noalias() += (weight * wu) * du * du.transpose();
            block.noalias() += (weight * wv) * dv * dv.transpose();
          }
        }
      }
      for (int a = 0; a < order; ++a) {
        const int row =
            surface.controlPointIndex(indexU - p + a / (q + 1), indexV - q + a % (q + 1));
        for (int b = 0; b < order; ++b) {
          const int column =
              surface.controlPointIndex(indexU - p + b / (q + 1), indexV - q + b % (q + 1));
          triplets.emplace_back(row, column, block(a, b));
        }
      }
    }
  }
  const int n = surface.countU() * surface.countV();
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  return matrix;
}

}  // namespace

Eigen::SparseMatrix<double> thinPlateMatrix(const BSplineSurface& surface) {
  return energyMatrix(surface, Energy::ThinPlate);
}

Eigen::SparseMatrix<double> membraneMatrix(const BSplineSurface& surface) {
  return energyMatrix(surface, Energy::Membrane);
}

}  // namespace d2vdb::detail
