// The fitting iteration's sparse model against a dense brute-force assembly of the same normal
// equations, including a model reused after the sensors moved into knot spans it had not seen.
#include "d2vdb/fit/QuadraticModel.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "FitTestSupport.h"
#include "d2vdb/fit/SensorBasis.h"
#include "d2vdb/fit/SmoothingMatrix.h"

namespace d2vdb {
namespace {

BSplineCurve closedCurve() {
  std::vector<Eigen::Vector3d> controls;
  for (int i = 0; i < 14; ++i) {
    const double angle = test::kTwoPi * i / 14;
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
/// of its normal equations, built from one Jacobian per sensor.
std::vector<Eigen::Vector3d> denseStep(const SensorBasis& basis,
                                       const std::vector<QuadraticForm>& forms,
                                       const Eigen::SparseMatrix<double>& smoothing,
                                       const std::vector<Eigen::Vector3d>& points) {
  const int n = static_cast<int>(points.size());
  Eigen::MatrixXd hessian = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  Eigen::VectorXd right = Eigen::VectorXd::Zero(3 * n);
  const double inverseCount = 1.0 / basis.sensorCount();
  for (int k = 0; k < basis.sensorCount(); ++k) {
    Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(3, 3 * n);  // d x_k / d P
    for (int j = 0; j < basis.order(); ++j) {
      jacobian.middleCols(3 * basis.index(k, j), 3) +=
          basis.weight(k, j) * Eigen::Matrix3d::Identity();
    }
    const QuadraticForm& form = forms[static_cast<std::size_t>(k)];
    hessian += inverseCount * jacobian.transpose() * form.A * jacobian;
    right += inverseCount * jacobian.transpose() * form.b;
  }
  const Eigen::MatrixXd dense = Eigen::MatrixXd(smoothing);
  Eigen::VectorXd current(3 * n);
  for (int i = 0; i < n; ++i) {
    current.segment<3>(3 * i) = points[static_cast<std::size_t>(i)];
    for (int j = 0; j < n; ++j) {
      hessian.block<3, 3>(3 * i, 3 * j) += dense(i, j) * Eigen::Matrix3d::Identity();
    }
  }
  const Eigen::VectorXd target = hessian.ldlt().solve(right);
  std::vector<Eigen::Vector3d> step(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    step[static_cast<std::size_t>(i)] = target.segment<3>(3 * i) - current.segment<3>(3 * i);
  }
  return step;
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

}  // namespace
}  // namespace d2vdb
