// The fitting iteration's sparse model against a dense brute-force assembly of the same normal
// equations, including a model reused after the sensors moved into knot spans it had not seen.
#include "d2vdb/fit/detail/QuadraticModel.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <optional>
#include <random>

#include "FitTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/fit/detail/SensorBasis.h"
#include "d2vdb/fit/detail/SmoothingMatrix.h"

namespace d2vdb::detail {
namespace {

BSplineCurve closedCurve(int controlPoints = 14) {
  std::vector<Eigen::Vector3d> controls;
  for (int i = 0; i < controlPoints; ++i) {
    const double angle = test::kTwoPi * i / controlPoints;
    controls.emplace_back(std::cos(angle), 0.8 * std::sin(angle), 0.1 * std::sin(3 * angle));
  }
  return BSplineCurve::closed(3, controls, 3);
}

/// Sensors at perSpan points of every knot span whose start lies in [from, to) of the domain.
std::vector<double> sensorsIn(const BSplineCurve& curve, double from, double to) {
  std::vector<double> parameters;
  for (const double t : uniformSensorParameters(curve, 4)) {
    const double fraction = (t - curve.domain().start) / curve.domain().length();
    if (fraction >= from && fraction < to) parameters.push_back(t);
  }
  return parameters;
}

/// A random symmetric positive definite form per sensor.
std::vector<QuadraticForm> randomForms(int count, unsigned seed) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<QuadraticForm> forms(static_cast<std::size_t>(count));
  for (QuadraticForm& form : forms) {
    Eigen::Matrix3d m;
    for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = uniform(engine);
    form.A = m.transpose() * m + 0.1 * Eigen::Matrix3d::Identity();
    form.b = Eigen::Vector3d(uniform(engine), uniform(engine), uniform(engine));
  }
  return forms;
}

/// The minimiser of (1/N) sum_k Q_k(x_k(P + c)) + sum_a (P + c)_a^T S (P + c)_a by a dense solve
/// of its normal equations, built from one Jacobian per sensor (from the basis' weights).
std::vector<Eigen::Vector3d> denseStep(const SensorMap& basis,
                                       const std::vector<QuadraticForm>& forms,
                                       const Eigen::SparseMatrix<double>& smoothing,
                                       const std::vector<Eigen::Vector3d>& points) {
  const int n = static_cast<int>(points.size());
  const auto jacobian = [&](int k) {
    Eigen::MatrixXd result = Eigen::MatrixXd::Zero(3, 3 * n);  // d x_k / d P
    for (int j = 0; j < basis.order(); ++j) {
      result.middleCols(3 * basis.index(k, j), 3) +=
          basis.weight(k, j) * Eigen::Matrix3d::Identity();
    }
    return result;
  };
  return test::denseModelStep(basis.sensorCount(), jacobian, forms, smoothing, points);
}

double largestDifference(const std::vector<Eigen::Vector3d>& a,
                         const std::vector<Eigen::Vector3d>& b) {
  double largest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, (a[i] - b[i]).norm());
  return largest;
}

TEST(QuadraticModel, SolveMatchesADenseSolveAndSurvivesNewSpans) {
  const BSplineCurve curve = closedCurve();
  const int n = curve.controlPointCount();
  const Eigen::SparseMatrix<double> smoothing = 1e-3 * derivativeGramMatrix(curve, 2);
  const std::vector<Eigen::Vector3d>& points = curve.controlPoints();

  // First solve: sensors on the first half of the curve only.
  const SensorBasis firstHalf(curve, sensorsIn(curve, 0.0, 0.5));
  const std::vector<QuadraticForm> firstForms = randomForms(firstHalf.sensorCount(), 1);
  QuadraticModel reused(n, 3, smoothing);
  const std::vector<Eigen::Vector3d> first = reused.solve(firstHalf, firstForms, points, 0.0);
  const std::vector<Eigen::Vector3d> firstReference =
      denseStep(firstHalf, firstForms, smoothing, points);
  EXPECT_LT(largestDifference(first, firstReference), 1e-9);

  // Second solve with the same model: sensors on the whole curve (spans the stored pattern lacks).
  const SensorBasis whole(curve, sensorsIn(curve, 0.0, 1.0));
  const std::vector<QuadraticForm> wholeForms = randomForms(whole.sensorCount(), 2);
  const std::vector<Eigen::Vector3d> second = reused.solve(whole, wholeForms, points, 0.0);
  const std::vector<Eigen::Vector3d> secondReference =
      denseStep(whole, wholeForms, smoothing, points);
  EXPECT_LT(largestDifference(second, secondReference), 1e-9);

  // A third solve on the grown pattern equals a fresh model's.
  QuadraticModel fresh(n, 3, smoothing);
  const std::vector<Eigen::Vector3d> again = reused.solve(firstHalf, firstForms, points, 0.0);
  EXPECT_LT(largestDifference(again, fresh.solve(firstHalf, firstForms, points, 0.0)), 1e-12);
  EXPECT_LT(largestDifference(again, firstReference), 1e-9);
}

/// The model's pieces as dense matrices over the stacked displacement (unknown 3 i + a): H and g
/// of m(c) = m(0) + g . c + c^T H c (no damping), summed sensor by sensor over the 3 x 3 blocks
/// of each pair of its control points.
struct DenseModel {
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
};

DenseModel denseModel(const std::vector<SensorTerms>& sets, double rankOneScale,
                      const Eigen::MatrixXd& smoothing,
                      const std::vector<Eigen::Vector3d>& points) {
  const int n = static_cast<int>(points.size());
  DenseModel model{Eigen::MatrixXd::Zero(3 * n, 3 * n), Eigen::VectorXd::Zero(3 * n)};
  for (const SensorTerms& set : sets) {
    const SensorMap& basis = *set.basis;
    for (int k = 0; k < basis.sensorCount(); ++k) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int j = 0; j < basis.order(); ++j) {
        x += basis.weight(k, j) * points[static_cast<std::size_t>(basis.index(k, j))];
      }
      const QuadraticForm& form = (*set.forms)[static_cast<std::size_t>(k)];
      for (int a = 0; a < basis.order(); ++a) {
        const int row = 3 * basis.index(k, a);
        model.g.segment<3>(row) += set.weight * 2.0 * basis.weight(k, a) * (form.A * x - form.b);
        for (int b = 0; b < basis.order(); ++b) {
          model.H.block<3, 3>(row, 3 * basis.index(k, b)) +=
              set.weight * basis.weight(k, a) * basis.weight(k, b) * form.A;
        }
      }
      if (set.rankOne == nullptr) continue;
      const RankOneTerms& terms = *set.rankOne;
      for (int t = terms.start[static_cast<std::size_t>(k)];
           t < terms.start[static_cast<std::size_t>(k) + 1]; ++t) {
        const Eigen::Map<const Eigen::VectorXd> u(
            terms.vectors.data() + static_cast<std::size_t>(t) * terms.length, terms.length);
        const double scale =
            set.weight * rankOneScale * terms.coefficients[static_cast<std::size_t>(t)];
        for (int a = 0; a < basis.order(); ++a) {
          for (int b = 0; b < basis.order(); ++b) {
            model.H.block<3, 3>(3 * basis.index(k, a), 3 * basis.index(k, b)) +=
                scale * u.segment<3>(3 * a) * u.segment<3>(3 * b).transpose();
          }
        }
      }
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      model.H.block<3, 3>(3 * i, 3 * j) += smoothing(i, j) * Eigen::Matrix3d::Identity();
      model.g.segment<3>(3 * i) += 2.0 * smoothing(i, j) * points[static_cast<std::size_t>(j)];
    }
  }
  return model;
}

std::vector<Eigen::Vector3d> unstack(const Eigen::VectorXd& v) {
  std::vector<Eigen::Vector3d> points(static_cast<std::size_t>(v.size() / 3));
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = v.segment<3>(3 * static_cast<Eigen::Index>(i));
  }
  return points;
}

/// The normwise backward error of the displacement c as a solution of H c = right (infinity
/// norms): |H c - right| / (|H| |c| + |right|), round-off (about n eps) for a stable solver.
double backwardError(const Eigen::MatrixXd& H, const std::vector<Eigen::Vector3d>& c,
                     const Eigen::VectorXd& right) {
  Eigen::VectorXd x(3 * static_cast<Eigen::Index>(c.size()));
  for (std::size_t i = 0; i < c.size(); ++i) x.segment<3>(3 * static_cast<Eigen::Index>(i)) = c[i];
  const double matrixNorm = H.cwiseAbs().rowwise().sum().maxCoeff();
  return (H * x - right).lpNorm<Eigen::Infinity>() /
         (matrixNorm * x.lpNorm<Eigen::Infinity>() + right.lpNorm<Eigen::Infinity>());
}

/// The curve's control-point count selects the solver: 14 (42 unknowns, a dense pattern) the
/// dense Cholesky, 200 (600 unknowns) the simplicial LDLT, 410 (1230 unknowns, over
/// QuadraticModel::kSimplicialUnknowns) the supernodal Cholesky.
class QuadraticModelSolvers : public ::testing::TestWithParam<int> {};

TEST_P(QuadraticModelSolvers, TwoSensorSetsRankOneTermsAndScaledSmoothingMatchADenseModel) {
  const BSplineCurve curve = closedCurve(GetParam());
  const int n = curve.controlPointCount();
  const std::vector<Eigen::Vector3d>& points = curve.controlPoints();
  // Two sets: one with rank-one terms (one positive, one negative per sensor), one without.
  const SensorBasis first(curve, sensorsIn(curve, 0.0, 1.0));
  const SensorBasis second(curve, sensorsIn(curve, 0.2, 0.7));
  const std::vector<QuadraticForm> firstForms = randomForms(first.sensorCount(), 3);
  const std::vector<QuadraticForm> secondForms = randomForms(second.sensorCount(), 4);
  RankOneTerms terms;
  const int length = 3 * first.order();
  terms.reset(first.sensorCount(), length);
  std::mt19937 engine(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int k = 0; k < first.sensorCount(); ++k) {
    for (const double alpha : {0.3, -0.05}) {
      terms.coefficients.push_back(alpha);
      for (int e = 0; e < length; ++e) terms.vectors.push_back(uniform(engine));
    }
    terms.start[static_cast<std::size_t>(k) + 1] = static_cast<int>(terms.coefficients.size());
  }
  const std::vector<SensorTerms> sets{{&first, &firstForms, 0.7, &terms},
                                      {&second, &secondForms, 0.2, nullptr}};
  const Eigen::SparseMatrix<double> fixed = 1e-3 * derivativeGramMatrix(curve, 1);
  const Eigen::SparseMatrix<double> bending = derivativeGramMatrix(curve, 2);
  const auto bendingForce = [&](double scale) {
    const Eigen::MatrixXd bendingDense = scale * Eigen::MatrixXd(bending);
    Eigen::VectorXd force(3 * n);
    for (int i = 0; i < n; ++i) {
      Eigen::Vector3d f = Eigen::Vector3d::Zero();
      for (int j = 0; j < n; ++j) f += bendingDense(i, j) * points[static_cast<std::size_t>(j)];
      force.segment<3>(3 * i) = f;
    }
    return force;
  };
  QuadraticModel model(n, 3, fixed, bending);
  model.setSmoothingScale(2e-4);
  model.assemble(sets, points);
  for (const double rankOneScale : {0.0, 0.5, 1.0}) {
    const std::vector<Eigen::Vector3d> step = model.solveAssembled(rankOneScale, 0.0);
    EXPECT_TRUE(model.lastSolvePositiveDefinite());
    const Eigen::MatrixXd smoothing = Eigen::MatrixXd(fixed) + 2e-4 * Eigen::MatrixXd(bending);
    const DenseModel dense = denseModel(sets, rankOneScale, smoothing, points);
    EXPECT_LT(backwardError(dense.H, step, -0.5 * dense.g), 1e-12) << rankOneScale;
    const Eigen::VectorXd minimizer = dense.H.partialPivLu().solve(-0.5 * dense.g);
    // The same system again (its factorisation is kept), and as a minimiser.
    EXPECT_EQ(model.solveAssembled(rankOneScale, 0.0), step);
    const std::optional<std::vector<Eigen::Vector3d>> minimized =
        model.minimizeAssembled(rankOneScale, 0.0);
    ASSERT_TRUE(minimized.has_value());
    EXPECT_EQ(*minimized, step);
    // m(0) - m(c) for the solution and for another displacement.
    const Eigen::VectorXd other = 0.3 * minimizer + 0.01 * Eigen::VectorXd::Ones(3 * n);
    for (const Eigen::VectorXd& c : {minimizer, other}) {
      const double expected = -(dense.g.dot(c) + c.dot(dense.H * c));
      EXPECT_NEAR(model.predictedDecrease(unstack(c)), expected, 1e-9 * std::abs(expected));
    }
    // The scaled smoothing's shift of the minimiser: H^-1 (sigma T P).
    EXPECT_LT(backwardError(dense.H, model.scaledSmoothingShift(), bendingForce(2e-4)), 1e-12);
  }
  // A new smoothing scale is a new system, not the kept factorisation's.
  model.setSmoothingScale(3e-3);
  const std::vector<Eigen::Vector3d> smoother = model.solveAssembled(1.0, 0.0);
  const DenseModel denseSmoother =
      denseModel(sets, 1.0, Eigen::MatrixXd(fixed) + 3e-3 * Eigen::MatrixXd(bending), points);
  EXPECT_LT(backwardError(denseSmoother.H, smoother, -0.5 * denseSmoother.g), 1e-12);

  // A dominant negative rank-one term makes the system indefinite, and the model says so: no
  // minimiser, and the stationary point on request.
  RankOneTerms negative = terms;
  for (double& alpha : negative.coefficients) alpha = -50.0;
  const std::vector<SensorTerms> indefiniteSets{{&first, &firstForms, 0.7, &negative}};
  model.assemble(indefiniteSets, points);
  EXPECT_FALSE(model.minimizeAssembled(1.0, 0.0).has_value());
  EXPECT_FALSE(model.lastSolvePositiveDefinite());
  const std::vector<Eigen::Vector3d> stationary = model.solveAssembled(1.0, 0.0);
  EXPECT_FALSE(model.lastSolvePositiveDefinite());
  const DenseModel denseIndefinite = denseModel(
      indefiniteSets, 1.0, Eigen::MatrixXd(fixed) + 3e-3 * Eigen::MatrixXd(bending), points);
  EXPECT_LT(backwardError(denseIndefinite.H, stationary, -0.5 * denseIndefinite.g), 1e-12);
  model.solveAssembled(0.0, 0.0);
  EXPECT_TRUE(model.lastSolvePositiveDefinite());
}

TEST_P(QuadraticModelSolvers, SeparableTermsSumLikeTheirExpandedVectors) {
  const BSplineCurve curve = closedCurve(GetParam());
  const int n = curve.controlPointCount();
  const std::vector<Eigen::Vector3d>& points = curve.controlPoints();
  const SensorBasis basis(curve, sensorsIn(curve, 0.0, 1.0));
  const std::vector<QuadraticForm> forms = randomForms(basis.sensorCount(), 6);
  // Up to two terms alpha ((w (x) t) . c)^2 per sensor, stored once by their directions t and
  // once expanded to u = w (x) t.
  RankOneTerms separable;
  RankOneTerms expanded;
  separable.reset(basis.sensorCount(), 3, true);
  expanded.reset(basis.sensorCount(), 3 * basis.order());
  std::mt19937 engine(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int k = 0; k < basis.sensorCount(); ++k) {
    for (int t = 0; t < k % 3; ++t) {
      const Eigen::Vector3d direction =
          Eigen::Vector3d(uniform(engine), uniform(engine), uniform(engine)).normalized();
      const double alpha = t == 0 ? 0.4 : -0.08;
      separable.coefficients.push_back(alpha);
      expanded.coefficients.push_back(alpha);
      for (int c = 0; c < 3; ++c) separable.vectors.push_back(direction[c]);
      for (int j = 0; j < basis.order(); ++j) {
        for (int c = 0; c < 3; ++c) expanded.vectors.push_back(basis.weight(k, j) * direction[c]);
      }
    }
    separable.start[static_cast<std::size_t>(k) + 1] =
        static_cast<int>(separable.coefficients.size());
    expanded.start[static_cast<std::size_t>(k) + 1] =
        static_cast<int>(expanded.coefficients.size());
  }
  const Eigen::SparseMatrix<double> fixed = 1e-3 * derivativeGramMatrix(curve, 2);
  QuadraticModel withSeparable(n, 3, fixed);
  QuadraticModel withExpanded(n, 3, fixed);
  withSeparable.assemble({{&basis, &forms, 0.5, &separable}}, points);
  withExpanded.assemble({{&basis, &forms, 0.5, &expanded}}, points);
  for (const double rankOneScale : {0.0, 0.7, 1.0}) {
    const std::vector<Eigen::Vector3d> step = withSeparable.solveAssembled(rankOneScale, 0.0);
    const DenseModel dense = denseModel({{&basis, &forms, 0.5, &expanded}}, rankOneScale,
                                        Eigen::MatrixXd(fixed), points);
    EXPECT_LT(backwardError(dense.H, step, -0.5 * dense.g), 1e-12) << rankOneScale;
    double size = 1.0;
    for (const Eigen::Vector3d& c : step) size = std::max(size, c.norm());
    EXPECT_LT(largestDifference(step, withExpanded.solveAssembled(rankOneScale, 0.0)), 1e-9 * size)
        << rankOneScale;
    EXPECT_EQ(withSeparable.lastSolvePositiveDefinite(), withExpanded.lastSolvePositiveDefinite());
  }
  // A separable set whose direction length is not the dimension is refused.
  RankOneTerms wrong = separable;
  wrong.length = 2;
  EXPECT_THROW(withSeparable.assemble({{&basis, &forms, 0.5, &wrong}}, points), InputError);
}

INSTANTIATE_TEST_SUITE_P(DenseSimplicialAndSupernodal, QuadraticModelSolvers,
                         ::testing::Values(14, 200, 410));

}  // namespace
}  // namespace d2vdb::detail
