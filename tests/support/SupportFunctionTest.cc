#include "d2vdb/support/SupportFunction.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "SupportTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/support/SphereQuadrature.h"
#include "d2vdb/support/detail/SupportDesign.h"

namespace d2vdb {
namespace {

SupportFunction randomFunction(int degree, unsigned seed, double decay = 0.7) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd c(harmonicCount(degree));
  for (int l = 0; l <= degree; ++l) {
    for (int m = -l; m <= l; ++m) c[harmonicIndex(l, m)] = std::pow(decay, l) * uniform(engine);
  }
  c[0] += 10.0;
  return SupportFunction(degree, c);
}

TEST(SupportFunction, SphereIsExact) {
  const Eigen::Vector3d center(0.25, -1.5, 3.0);
  const double radius = 1.75;
  const SupportFunction h = SupportFunction::sphere(center, radius, 6);
  for (const Eigen::Vector3d& n : test::randomUnitVectors(200, 1)) {
    const SupportPoint sp = h.evaluate(n);
    EXPECT_NEAR(sp.value, radius + center.dot(n), 1e-13);
    EXPECT_LT((sp.point - (center + radius * n)).norm(), 1e-13);
    EXPECT_NEAR(sp.radius1, radius, 1e-13);
    EXPECT_NEAR(sp.radius2, radius, 1e-13);
    EXPECT_NEAR(sp.gaussianCurvature(), 1.0 / (radius * radius), 1e-13);
    EXPECT_NEAR(sp.meanCurvature(), 1.0 / radius, 1e-13);
  }
  // Exactly at the poles, where polar coordinates would be singular.
  for (const Eigen::Vector3d& n : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1)}) {
    EXPECT_LT((h.point(n) - (center + radius * n)).norm(), 1e-13);
  }
  EXPECT_LT((h.linearPart() - center).norm(), 1e-14);
  EXPECT_NEAR(h.meanValue(), radius, 1e-14);
}

TEST(SupportFunction, OffsetAndTranslationAreExactAndTouchOnlyDegreesZeroAndOne) {
  const SupportFunction h = randomFunction(10, 5);
  const double d = -0.37;
  const Eigen::Vector3d t(0.5, -2.0, 1.25);
  const SupportFunction moved = h.offset(d).translated(t);
  for (Eigen::Index j = 4; j < h.coefficients().size(); ++j) {
    EXPECT_EQ(moved.coefficients()[j], h.coefficients()[j]);
  }
  const auto normals = test::randomUnitVectors(300, 2);
  const auto before = h.evaluate(normals);
  const auto after = moved.evaluate(normals);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    EXPECT_LT((after[i].point - (before[i].point + d * before[i].normal + t)).norm(), 1e-12);
    EXPECT_NEAR(after[i].radius1, before[i].radius1 + d, 1e-12);
    EXPECT_NEAR(after[i].radius2, before[i].radius2 + d, 1e-12);
  }
  const auto offsetPoints = h.points(normals, d);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    EXPECT_LT((offsetPoints[i] - (before[i].point + d * normals[i])).norm(), 1e-12);
  }
}

TEST(SupportFunction, RotationComposesWithTheInverseRotation) {
  const SupportFunction h = randomFunction(12, 9);
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.83, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const SupportFunction turned = h.rotated(rotation);
  for (const Eigen::Vector3d& n : test::randomUnitVectors(100, 4)) {
    EXPECT_NEAR(turned.value(n), h.value(rotation.transpose() * n), 1e-12);
    EXPECT_LT((turned.point(n) - rotation * h.point(rotation.transpose() * n)).norm(), 1e-11);
  }
  EXPECT_THROW(h.rotated(2.0 * Eigen::Matrix3d::Identity()), InputError);
  EXPECT_THROW(h.rotated(-Eigen::Matrix3d::Identity()), InputError);
}

// The surface gradient and Hess_S h + h I against finite differences along great circles: for a
// unit tangent e at n, h(cos t n + sin t e) has first derivative e . grad_S h and second
// derivative e^T Hess_S h e at t = 0 (great circles are geodesics).
TEST(SupportFunction, DerivativesMatchFiniteDifferencesAlongGreatCircles) {
  const SupportFunction h = randomFunction(8, 11);
  for (const Eigen::Vector3d& n : test::randomUnitVectors(20, 6)) {
    const SupportPoint sp = h.evaluate(n);
    Eigen::Vector3d e1 = n.unitOrthogonal();
    Eigen::Vector3d e2 = n.cross(e1);
    const auto along = [&](const Eigen::Vector3d& e, double t) {
      return h.value(std::cos(t) * n + std::sin(t) * e);
    };
    const double step = 1e-3;
    const auto second = [&](const Eigen::Vector3d& e) {
      return (-along(e, 2 * step) + 16 * along(e, step) - 30 * sp.value + 16 * along(e, -step) -
              along(e, -2 * step)) /
             (12 * step * step);
    };
    const auto first = [&](const Eigen::Vector3d& e) {
      return (-along(e, 2 * step) + 8 * along(e, step) - 8 * along(e, -step) +
              along(e, -2 * step)) /
             (12 * step);
    };
    EXPECT_NEAR(sp.surfaceGradient.dot(e1), first(e1), 1e-8);
    EXPECT_NEAR(sp.surfaceGradient.dot(e2), first(e2), 1e-8);
    EXPECT_NEAR(sp.surfaceGradient.dot(n), 0.0, 1e-14);
    // W = Hess_S h + h I in the frame (e1, e2), from second derivatives along e1, e2, e1 + e2.
    const double w11 = second(e1) + sp.value;
    const double w22 = second(e2) + sp.value;
    const double wDiag = second((e1 + e2).normalized()) + sp.value;
    const double w12 = wDiag - 0.5 * (w11 + w22);
    Eigen::Matrix2d w;
    w << w11, w12, w12, w22;
    const Eigen::Vector2d radii = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(w).eigenvalues();
    EXPECT_NEAR(sp.radius1, radii[0], 1e-5);
    EXPECT_NEAR(sp.radius2, radii[1], 1e-5);
    // Principal directions: W d_i = r_i d_i.
    const Eigen::Vector2d d1(sp.direction1.dot(e1), sp.direction1.dot(e2));
    EXPECT_LT((w * d1 - sp.radius1 * d1).norm(), 1e-5);
    EXPECT_NEAR(sp.direction1.dot(n), 0.0, 1e-14);
    EXPECT_NEAR(sp.direction1.cross(sp.direction2).dot(n), 1.0, 1e-14);
  }
}

TEST(SupportFunction, ProjectedEllipsoidConvergesToTheExactSurface) {
  // Orthogonal projection of h = |A n| onto the harmonics of degree <= L by exact quadrature:
  // x_h must approach A^2 n / |A n| as L grows, radii the analytic ones.
  const test::Ellipsoid ellipsoid;
  const SphereQuadrature rule = sphereQuadrature(120);
  const int degree = 24;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(harmonicCount(degree));
  for (std::size_t q = 0; q < rule.nodes.size(); ++q) {
    c += rule.weights[q] * ellipsoid.support(rule.nodes[q]) *
         evaluateHarmonics(degree, rule.nodes[q]);
  }
  const auto normals = test::randomUnitVectors(2000, 8);
  double previous = 1e9;
  for (const int l : {8, 16, 24}) {
    const SupportFunction h = SupportFunction(degree, c).withDegree(l);
    double worst = 0.0;
    for (const auto& sp : h.evaluate(normals)) {
      worst = std::max(worst, (sp.point - ellipsoid.point(sp.normal)).norm());
    }
    EXPECT_LT(worst, previous / 10.0) << "degree " << l;
    previous = worst;
  }
  EXPECT_LT(previous, 1e-5 * ellipsoid.a);
  const SupportPoint tip = SupportFunction(degree, c).evaluate(Eigen::Vector3d::UnitX());
  EXPECT_NEAR(tip.radius1, ellipsoid.c * ellipsoid.c / ellipsoid.a, 1e-3);
  EXPECT_NEAR(tip.radius2, ellipsoid.b * ellipsoid.b / ellipsoid.a, 1e-3);
}

TEST(SupportFunction, BatchEvaluationIsDeterministicAndMatchesSingleEvaluation) {
  const SupportFunction h = randomFunction(16, 21);
  const auto normals = test::randomUnitVectors(1000, 12);
  const auto one = test::withThreads(1, [&] { return h.evaluate(normals); });
  const auto two = test::withThreads(2, [&] { return h.evaluate(normals); });
  const auto pointsOne = test::withThreads(1, [&] { return h.points(normals, 0.1); });
  const auto pointsTwo = test::withThreads(2, [&] { return h.points(normals, 0.1); });
  for (std::size_t i = 0; i < normals.size(); ++i) {
    EXPECT_EQ(one[i].point, two[i].point);
    EXPECT_EQ(one[i].radius1, two[i].radius1);
    EXPECT_EQ(one[i].radius2, two[i].radius2);
    EXPECT_EQ(pointsOne[i], pointsTwo[i]);
    const SupportPoint single = h.evaluate(normals[i]);
    EXPECT_EQ(single.point, one[i].point);
    EXPECT_EQ(single.radius1, one[i].radius1);
  }
}

// The evaluation kernel (all quantities from one pass over the harmonics per order) against
// independent references at degree 24: h from the harmonic values, x_h from the explicit design
// matrix (harmonic values and derivative ladders assembled separately), and the sum of the radii
// from the spherical Laplacian, r1 + r2 = tr(Hess_S h + h I) = Delta_S h + 2 h with
// Delta_S Y_l = -l (l + 1) Y_l.
TEST(SupportFunction, EvaluationMatchesTheHarmonicBasisAtHighDegree) {
  const int degree = 24;
  const SupportFunction h = randomFunction(degree, 31, 0.9);
  const auto normals = test::randomUnitVectors(300, 14);
  const std::vector<SupportPoint> points = h.evaluate(normals);
  const Eigen::MatrixXd design = detail::supportDesignMatrix(normals, degree);
  const Eigen::VectorXd x = design * h.coefficients();
  Eigen::VectorXd laplacianWeights(harmonicCount(degree));
  for (int l = 0; l <= degree; ++l) {
    for (int m = -l; m <= l; ++m) laplacianWeights[harmonicIndex(l, m)] = 2.0 - l * (l + 1.0);
  }
  const Eigen::VectorXd traceCoefficients = laplacianWeights.cwiseProduct(h.coefficients());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const Eigen::VectorXd y = evaluateHarmonics(degree, normals[i]);
    EXPECT_NEAR(points[i].value, y.dot(h.coefficients()), 1e-12);
    const Eigen::Vector3d reference = x.segment<3>(3 * static_cast<Eigen::Index>(i));
    EXPECT_LT((points[i].point - reference).norm(), 1e-11);
    EXPECT_NEAR(points[i].radius1 + points[i].radius2, y.dot(traceCoefficients), 1e-9);
  }
  const std::vector<Eigen::Vector3d> offsetPoints = h.points(normals, 0.25);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    EXPECT_LT((offsetPoints[i] - points[i].point - 0.25 * normals[i]).norm(), 1e-12);
  }
}

TEST(SupportFunction, RejectsBadConstructionAndNormals) {
  EXPECT_THROW(SupportFunction(-1, Eigen::VectorXd::Zero(1)), InputError);
  EXPECT_THROW(SupportFunction(2, Eigen::VectorXd::Zero(8)), InputError);
  Eigen::VectorXd nan = Eigen::VectorXd::Zero(4);
  nan[2] = std::nan("");
  EXPECT_THROW(SupportFunction(1, nan), InputError);
  const SupportFunction h = SupportFunction::sphere(Eigen::Vector3d::Zero(), 1.0);
  EXPECT_THROW(h.value(Eigen::Vector3d::Zero()), InputError);
  EXPECT_NEAR(h.value(Eigen::Vector3d(1e300, 1e300, 0)), 1.0, 1e-15);  // no overflow
  EXPECT_THROW(h.evaluate(Eigen::Vector3d(std::nan(""), 0, 1)), InputError);
  EXPECT_THROW(h.offset(std::numeric_limits<double>::infinity()), InputError);
  EXPECT_THROW(h.withDegree(kMaxSupportDegree + 1), InputError);
}

}  // namespace
}  // namespace d2vdb
