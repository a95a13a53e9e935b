// Surface sensors and the quadratic model over a surface: sensor positions against direct surface
// evaluation, the cell grouping, and one model solve against a dense solve whose Jacobian comes
// from evaluating the surface with unit control points (independent of the basis tables).
#include "d2vdb/fit/detail/SurfaceSensorBasis.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <set>

#include "FitTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/fit/detail/QuadraticModel.h"
#include "d2vdb/fit/detail/ThinPlateMatrix.h"

namespace d2vdb::detail {
namespace {

BSplineSurface randomSurface(unsigned seed, int p, int q, int nu, int nv, bool closedU,
                             bool closedV) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < nu * nv; ++i) {
    points.emplace_back(uniform(engine), uniform(engine), uniform(engine));
  }
  KnotVector knotsU = closedU ? KnotVector::periodic(p, nu, {0.0, 3.0}) : KnotVector(p, [&] {
    // Clamped with uneven interior knots.
    std::vector<double> knots(static_cast<std::size_t>(p + 1), 0.0);
    for (int i = 1; i < nu - p; ++i) {
      knots.push_back(3.0 * std::pow(double(i) / (nu - p), 1.3));
    }
    knots.insert(knots.end(), static_cast<std::size_t>(p + 1), 3.0);
    return knots;
  }());
  KnotVector knotsV =
      closedV ? KnotVector::periodic(q, nv, {-1.0, 1.0}) : KnotVector::clamped(q, nv, {-1.0, 1.0});
  return BSplineSurface(std::move(knotsU), std::move(knotsV), points, closedU, closedV);
}

TEST(SurfaceSensorBasis, PositionsMatchTheSurfaceAndCellsShareControlPoints) {
  for (const auto& [p, q, closedU, closedV] :
       {std::tuple{3, 3, false, false}, std::tuple{3, 3, true, true}, std::tuple{1, 3, false, true},
        std::tuple{2, 3, true, false}}) {
    const BSplineSurface surface = randomSurface(4, p, q, 7, 6, closedU, closedV);
    const std::vector<Eigen::Vector2d> parameters = uniformSurfaceSensorParameters(surface, 3);
    const int valuesU = 3 * (closedU ? 7 : 7 - p) + (closedU ? 0 : 2);
    const int valuesV = 3 * (closedV ? 6 : 6 - q) + (closedV ? 0 : 2);
    ASSERT_EQ(static_cast<int>(parameters.size()), valuesU * valuesV);
    const SurfaceSensorBasis basis(surface, parameters);
    EXPECT_EQ(basis.order(), (p + 1) * (q + 1));
    const std::vector<Eigen::Vector3d> positions = basis.positions(surface.controlPoints());
    for (int k = 0; k < basis.sensorCount(); ++k) {
      const Eigen::Vector3d expected = surface.evaluate(
          parameters[static_cast<std::size_t>(k)].x(), parameters[static_cast<std::size_t>(k)].y());
      EXPECT_LT((positions[static_cast<std::size_t>(k)] - expected).norm(), 1e-13);
      double sum = 0.0;
      for (int j = 0; j < basis.order(); ++j) sum += basis.weight(k, j);
      EXPECT_NEAR(sum, 1.0, 1e-14);
    }
    // Every group's sensors use the same control points; groups are disjoint and cover all.
    std::set<int> seen;
    for (std::size_t g = 0; g + 1 < basis.spanBegin().size(); ++g) {
      const int first = basis.spanOrder()[static_cast<std::size_t>(basis.spanBegin()[g])];
      for (int i = basis.spanBegin()[g]; i < basis.spanBegin()[g + 1]; ++i) {
        const int k = basis.spanOrder()[static_cast<std::size_t>(i)];
        EXPECT_TRUE(seen.insert(k).second);
        for (int j = 0; j < basis.order(); ++j) EXPECT_EQ(basis.index(k, j), basis.index(first, j));
      }
    }
    EXPECT_EQ(static_cast<int>(seen.size()), basis.sensorCount());
  }
}

TEST(SurfaceSensorBasis, BadParametersAreRejected) {
  const BSplineSurface surface = randomSurface(5, 3, 3, 5, 5, false, true);
  EXPECT_THROW(SurfaceSensorBasis(surface, {Eigen::Vector2d(3.5, 0.0)}), InputError);
  EXPECT_THROW(SurfaceSensorBasis(surface, {Eigen::Vector2d(1.0, std::nan(""))}), InputError);
  EXPECT_NO_THROW(SurfaceSensorBasis(surface, {Eigen::Vector2d(1.0, 7.3)}));  // closed in v: wraps
  EXPECT_THROW(uniformSurfaceSensorParameters(surface, 0), InputError);
}

TEST(SurfaceSensorBasis, ModelSolveMatchesADenseSolve) {
  const BSplineSurface surface = randomSurface(6, 3, 2, 6, 5, true, false);
  const int n = surface.countU() * surface.countV();
  const SurfaceSensorBasis basis(surface, uniformSurfaceSensorParameters(surface, 2));
  std::mt19937 engine(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<QuadraticForm> forms(static_cast<std::size_t>(basis.sensorCount()));
  for (QuadraticForm& form : forms) {
    Eigen::Matrix3d m;
    for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = uniform(engine);
    form.A = m.transpose() * m + 0.05 * Eigen::Matrix3d::Identity();
    form.b = Eigen::Vector3d(uniform(engine), uniform(engine), uniform(engine));
  }
  const Eigen::SparseMatrix<double> smoothing = 1e-3 * thinPlateMatrix(surface);
  QuadraticModel model(n, 3, smoothing);
  const std::vector<Eigen::Vector3d>& points = surface.controlPoints();
  const std::vector<Eigen::Vector3d> step = model.solve(basis, forms, points, 0.0);

  // Dense: the Jacobian column of control point m is the surface evaluated with P = e_m.
  Eigen::MatrixXd basisValues(basis.sensorCount(), n);
  for (int m = 0; m < n; ++m) {
    std::vector<Eigen::Vector3d> unit(static_cast<std::size_t>(n), Eigen::Vector3d::Zero());
    unit[static_cast<std::size_t>(m)] = Eigen::Vector3d::Ones();
    BSplineSurface indicator = surface;
    indicator.setControlPoints(unit);
    for (int k = 0; k < basis.sensorCount(); ++k) {
      basisValues(k, m) = indicator.evaluate(basis.parameter(k).x(), basis.parameter(k).y()).x();
    }
  }
  const auto jacobian = [&](int k) {
    Eigen::MatrixXd result = Eigen::MatrixXd::Zero(3, 3 * n);
    for (int m = 0; m < n; ++m) {
      result.middleCols(3 * m, 3) = basisValues(k, m) * Eigen::Matrix3d::Identity();
    }
    return result;
  };
  const std::vector<Eigen::Vector3d> reference =
      test::denseModelStep(basis.sensorCount(), jacobian, forms, smoothing, points);
  for (int i = 0; i < n; ++i) {
    EXPECT_LT((step[static_cast<std::size_t>(i)] - reference[static_cast<std::size_t>(i)]).norm(),
              1e-9);
  }
}

TEST(SurfaceSensorBasis, TensorFactorsAndParameterKeys) {
  const BSplineSurface surface = randomSurface(9, 3, 2, 7, 6, false, true);
  std::vector<Eigen::Vector2d> parameters = uniformSurfaceSensorParameters(surface, 2);
  parameters.emplace_back(1.234, 0.321);
  parameters.emplace_back(1.234, -0.5);
  const SurfaceSensorBasis basis(surface, parameters);
  ASSERT_EQ(basis.orderU(), 4);
  for (int k = 0; k < basis.sensorCount(); ++k) {
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 3; ++b) {
        EXPECT_EQ(basis.weight(k, a * 3 + b), basis.uWeight(k, a) * basis.vWeight(k, b));
      }
    }
    for (int other = 0; other < basis.sensorCount(); other += 7) {
      EXPECT_EQ(basis.uKey(k) == basis.uKey(other),
                basis.parameter(k).x() == basis.parameter(other).x());
      EXPECT_EQ(basis.vKey(k) == basis.vKey(other),
                basis.parameter(k).y() == basis.parameter(other).y());
    }
  }
}

/// The model over a surface with forms and separable second-order terms against a dense assembly
/// from the surface's own evaluation: sensors on a grid in every knot cell (summed direction by
/// direction) plus scattered sensors that break the grid of their cells (summed sensor by sensor).
TEST(SurfaceSensorBasis, ModelWithSecondOrderTermsMatchesADenseModel) {
  const BSplineSurface surface = randomSurface(10, 3, 2, 6, 5, true, false);
  const int n = surface.countU() * surface.countV();
  std::vector<Eigen::Vector2d> parameters = uniformSurfaceSensorParameters(surface, 3);
  std::mt19937 engine(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int extra = 0; extra < 5; ++extra) {
    parameters.emplace_back(1.5 + 1.5 * uniform(engine), 0.9 * uniform(engine));
  }
  const SurfaceSensorBasis basis(surface, parameters);
  const int count = basis.sensorCount();
  std::vector<QuadraticForm> forms(static_cast<std::size_t>(count));
  RankOneTerms terms;
  terms.reset(count, 3, true);
  for (int k = 0; k < count; ++k) {
    QuadraticForm& form = forms[static_cast<std::size_t>(k)];
    Eigen::Matrix3d m;
    for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = uniform(engine);
    form.A = m.transpose() * m + 0.05 * Eigen::Matrix3d::Identity();
    form.b = Eigen::Vector3d(uniform(engine), uniform(engine), uniform(engine));
    for (const double alpha : {0.3, -0.02}) {
      const Eigen::Vector3d t =
          Eigen::Vector3d(uniform(engine), uniform(engine), uniform(engine)).normalized();
      terms.coefficients.push_back(alpha);
      for (int c = 0; c < 3; ++c) terms.vectors.push_back(t[c]);
    }
    terms.start[static_cast<std::size_t>(k) + 1] = static_cast<int>(terms.coefficients.size());
  }
  const Eigen::SparseMatrix<double> smoothing = 1e-3 * thinPlateMatrix(surface);
  const std::vector<Eigen::Vector3d>& points = surface.controlPoints();
  const double weight = 0.7;
  QuadraticModel model(n, 3, smoothing);
  model.assemble({SensorTerms{&basis, &forms, weight, &terms}}, points);

  // Dense: basis values from the surface evaluated with P = e_m.
  Eigen::MatrixXd values(count, n);
  for (int m = 0; m < n; ++m) {
    std::vector<Eigen::Vector3d> unit(static_cast<std::size_t>(n), Eigen::Vector3d::Zero());
    unit[static_cast<std::size_t>(m)] = Eigen::Vector3d::Ones();
    BSplineSurface indicator = surface;
    indicator.setControlPoints(unit);
    for (int k = 0; k < count; ++k) {
      values(k, m) = indicator.evaluate(basis.parameter(k).x(), basis.parameter(k).y()).x();
    }
  }
  for (const double rankOneScale : {0.0, 1.0}) {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    Eigen::VectorXd halfGradient = Eigen::VectorXd::Zero(3 * n);
    for (int k = 0; k < count; ++k) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int m = 0; m < n; ++m) x += values(k, m) * points[static_cast<std::size_t>(m)];
      const QuadraticForm& form = forms[static_cast<std::size_t>(k)];
      Eigen::Matrix3d block = form.A;
      for (int t = terms.start[static_cast<std::size_t>(k)];
           t < terms.start[static_cast<std::size_t>(k) + 1]; ++t) {
        const Eigen::Map<const Eigen::Vector3d> direction(terms.vectors.data() + 3 * t);
        block += rankOneScale * terms.coefficients[static_cast<std::size_t>(t)] * direction *
                 direction.transpose();
      }
      for (int a = 0; a < n; ++a) {
        if (values(k, a) == 0.0) continue;
        halfGradient.segment<3>(3 * a) += weight * values(k, a) * (form.A * x - form.b);
        for (int b = 0; b < n; ++b) {
          H.block<3, 3>(3 * a, 3 * b) += weight * values(k, a) * values(k, b) * block;
        }
      }
    }
    const Eigen::MatrixXd dense(smoothing);
    for (int a = 0; a < n; ++a) {
      for (int b = 0; b < n; ++b) {
        H.block<3, 3>(3 * a, 3 * b) += dense(a, b) * Eigen::Matrix3d::Identity();
        halfGradient.segment<3>(3 * a) += dense(a, b) * points[static_cast<std::size_t>(b)];
      }
    }
    const Eigen::VectorXd reference = H.partialPivLu().solve(-halfGradient);
    const std::vector<Eigen::Vector3d> step = model.solveAssembled(rankOneScale, 0.0);
    for (int i = 0; i < n; ++i) {
      EXPECT_LT((step[static_cast<std::size_t>(i)] - reference.segment<3>(3 * i)).norm(),
                1e-9 * (1.0 + reference.norm()))
          << "control point " << i << ", rank-one scale " << rankOneScale;
    }
  }
}

TEST(SurfaceSensorBasis, SameSensorsWithOneAndTwoThreads) {
  const BSplineSurface surface = randomSurface(8, 3, 3, 12, 10, true, true);
  const auto parameters = uniformSurfaceSensorParameters(surface, 5);
  const SurfaceSensorBasis one =
      test::withThreads(1, [&] { return SurfaceSensorBasis(surface, parameters); });
  const SurfaceSensorBasis two =
      test::withThreads(2, [&] { return SurfaceSensorBasis(surface, parameters); });
  for (int k = 0; k < one.sensorCount(); ++k) {
    for (int j = 0; j < one.order(); ++j) {
      EXPECT_EQ(one.weight(k, j), two.weight(k, j));
      EXPECT_EQ(one.index(k, j), two.index(k, j));
    }
  }
  EXPECT_EQ(one.spanOrder(), two.spanOrder());
}

}  // namespace
}  // namespace d2vdb::detail
