// Surfaces represented by their support function h(n) = x(n) . n over the sphere of normals
// (Gravesen, Juettler, Sir, "Approximating offsets of surfaces by using the support function
// representation", 2008; Sir, Gravesen, Juettler, "Curves and surfaces represented by
// polynomial support functions", Theoretical Computer Science 392, 2008).
#pragma once

#include <Eigen/Core>

#include <memory>
#include <vector>

#include "d2vdb/support/SphericalHarmonics.h"

namespace d2vdb {

namespace detail {
struct SupportEvaluator;
}

/// The differential geometry of a support-function surface at one unit normal n (Sir, Gravesen
/// and Juettler 2008, Theorem 1). Lengths in world units.
/// - point = x_h(n) = h(n) n + grad_S h(n): the surface point whose unit normal is n.
/// - radius1 <= radius2: the principal radii of curvature, the eigenvalues of Hess_S h + h I on
///   the tangent plane of n; direction1, direction2 the matching unit principal directions
///   (tangent to the surface there, (direction1, direction2, n) right-handed).
/// - Curvatures are the reciprocals of the radii, positive where the surface bends away from its
///   normal (a sphere of radius R with outward normals has radii R and curvatures 1/R); a radius
///   of zero (a point of the parabolic set, where x_h is singular) gives an infinite curvature.
struct SupportPoint {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();          ///< n, unit
  double value = 0.0;                                         ///< h(n)
  Eigen::Vector3d surfaceGradient = Eigen::Vector3d::Zero();  ///< grad_S h(n), orthogonal to n
  Eigen::Vector3d point = Eigen::Vector3d::Zero();            ///< x_h(n)
  double radius1 = 0.0;                                       ///< smaller principal radius
  double radius2 = 0.0;                                       ///< larger principal radius
  Eigen::Vector3d direction1 = Eigen::Vector3d::UnitX();      ///< principal direction of radius1
  Eigen::Vector3d direction2 = Eigen::Vector3d::UnitY();      ///< principal direction of radius2

  /// det(Hess_S h + h I) = radius1 * radius2: x_h is regular at n exactly when it is non-zero.
  double determinant() const { return radius1 * radius2; }
  /// 1 / radius1 (the larger curvature of a convex surface).
  double curvature1() const { return 1.0 / radius1; }
  /// 1 / radius2.
  double curvature2() const { return 1.0 / radius2; }
  /// Gaussian curvature K = 1 / det(Hess_S h + h I).
  double gaussianCurvature() const { return 1.0 / determinant(); }
  /// Mean curvature H = (curvature1 + curvature2) / 2 = tr(Hess_S h + h I) / (2 det).
  double meanCurvature() const { return 0.5 * (radius1 + radius2) / determinant(); }
};

/// A support function h: S^2 -> R in the span of the real spherical harmonics of degree <= L
/// (SphericalHarmonics.h), i.e. the polynomials of degree <= L in n restricted to the sphere.
/// Every polynomial of degree <= 1 is in the span, so offsetting (h + d) and translating
/// (h + c . n) stay exact. The map h -> x_h is linear.
///
/// Evaluation never uses polar angles: h is extended off the sphere by the polynomial P = sum_j
/// c_j r^l_j Y_j (each harmonic as its solid harmonic), whose gradient and Hessian come from exact
/// ladder relations between solid harmonics, and then grad_S h = (I - n n^T) grad P and
/// Hess_S h + h I = T (Hess P) T + (P - n . grad P) T with T = I - n n^T.
///
/// Copies are cheap (the evaluation tables are shared). Thread-safe for concurrent const use.
class SupportFunction {
 public:
  /// h = 0 (the surface is the origin), degree 0.
  SupportFunction();
  /// h = sum_j coefficients[j] Y_j with harmonicCount(degree) coefficients in harmonicIndex
  /// order. Throws InputError for a degree outside 0..kMaxSupportDegree, a wrong number of
  /// coefficients, or a non-finite coefficient.
  SupportFunction(int degree, Eigen::VectorXd coefficients);

  /// The support function of the sphere with the given centre and radius: h(n) = radius +
  /// centre . n, in degree `degree` >= 1 (higher coefficients zero). Throws InputError for a
  /// non-finite centre or radius or a degree outside 1..kMaxSupportDegree.
  static SupportFunction sphere(const Eigen::Vector3d& center, double radius, int degree = 1);

  /// The highest spherical-harmonic degree L.
  int degree() const { return degree_; }
  /// The (L + 1)^2 coefficients, in harmonicIndex order.
  const Eigen::VectorXd& coefficients() const { return coefficients_; }

  /// h(n). `normal` need not be unit: it is normalised first. Throws InputError for a zero or
  /// non-finite vector. (So do all the evaluation functions below.)
  double value(const Eigen::Vector3d& normal) const;
  /// x_h(n) + offset * n, the point of the offset surface at distance `offset` with normal n.
  Eigen::Vector3d point(const Eigen::Vector3d& normal, double offset = 0.0) const;
  /// Everything at one normal (see SupportPoint).
  SupportPoint evaluate(const Eigen::Vector3d& normal) const;

  /// evaluate() at every normal, in parallel (TBB). Each normal's arithmetic involves that normal
  /// only, so the result is bitwise identical for any thread count and to single-normal
  /// evaluate().
  std::vector<SupportPoint> evaluate(const std::vector<Eigen::Vector3d>& normals) const;
  /// point(n, offset) at every normal, in parallel; same determinism as evaluate().
  std::vector<Eigen::Vector3d> points(const std::vector<Eigen::Vector3d>& normals,
                                      double offset = 0.0) const;

  /// The support function of the offset surface at signed distance `distance` (along the
  /// normals): h + distance. Only the degree-0 coefficient changes. Throws InputError for a
  /// non-finite distance.
  SupportFunction offset(double distance) const;
  /// The support function of the surface translated by `translation`: h + translation . n. Only
  /// the three degree-1 coefficients change. Throws InputError for a non-finite translation.
  SupportFunction translated(const Eigen::Vector3d& translation) const;
  /// The support function of the surface rotated by `rotation` about the origin (x -> R x):
  /// h(R^T n). Each degree is rotated on its own, by exact quadrature of the products of
  /// harmonics (the result reproduces h(R^T n) to rounding). Throws InputError unless `rotation`
  /// is orthogonal with determinant +1 to within 1e-9.
  SupportFunction rotated(const Eigen::Matrix3d& rotation) const;
  /// The same function in another degree: higher coefficients are dropped (truncation of the
  /// harmonic expansion) or added as zeros. Throws InputError for a degree outside
  /// 0..kMaxSupportDegree.
  SupportFunction withDegree(int degree) const;

  /// The vector c of the degree-1 part c . n of h. For a closed convex surface this is its
  /// Steiner point (Groemer, Geometric Applications of Fourier Series and Spherical Harmonics,
  /// 1996, sec. 5.1).
  Eigen::Vector3d linearPart() const;
  /// The mean of h over the sphere: half the mean width of a closed convex surface.
  double meanValue() const;

 private:
  int degree_ = 0;
  Eigen::VectorXd coefficients_;
  std::shared_ptr<const detail::SupportEvaluator> evaluator_;
};

}  // namespace d2vdb
