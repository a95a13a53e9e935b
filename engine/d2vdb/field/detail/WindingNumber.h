// The generalised winding number of a triangle mesh, evaluated exactly or hierarchically with a
// certified error bound.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "d2vdb/mesh/TriangleBvh.h"

namespace d2vdb::detail {

/// Signed solid angle of the triangle (a, b, c) seen from the origin, in steradians, in
/// (-2 pi, 2 pi): positive when the origin lies behind the triangle (on the side its right-hand
/// normal (b - a) x (c - a) points away from). Van Oosterom and Strackee, "The solid angle of a
/// plane triangle", IEEE Trans. Biomedical Engineering 30(2), 1983.
double solidAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// w(q) = sum over triangles of their solid angle seen from q, divided by 4 pi (Jacobson, Kavan,
/// Sorkine-Hornung, "Robust inside-outside segmentation using generalized winding numbers",
/// SIGGRAPH 2013). For a closed, consistently oriented mesh (every edge crossed as often in
/// each direction) it is an integer off the surface: 1 inside an outward-wound shell, 0 outside,
/// and it jumps by -1 across each triangle in the direction of its normal. For open meshes it is
/// a smooth function whose 1/2-level closes holes.
///
/// Evaluation follows Barill, Dickson, Schmidt, Levin, Jacobson, "Fast winding numbers for soups
/// and clouds", SIGGRAPH 2018: a bounding-volume hierarchy whose nodes carry the Taylor
/// expansion, to second order about the area-weighted centroid, of their triangles' double-layer
/// potential integral of (x - q) . n / |x - q|^3 dA; a node whose expansion centre is more than
/// `beta` times its radius r from q answers with its expansion, nearer nodes open, and leaves sum
/// exact solid angles.
///
/// Unlike the paper, every evaluation also returns a bound on its error: the Taylor remainder of
/// the integrand, a fourth derivative of 1/|y|, whose symmetric 4-linear form has the same norm as
/// its diagonal (Banach's theorem on symmetric multilinear forms, 1938), 4!/|y|^5 (Legendre
/// polynomials are bounded by 1). For a node of unsigned area A this gives
/// |error| <= A r^3 / (pi rho^5), where rho >= R - r is a lower bound of the distance from q to the
/// node (the larger of R - r and the distance to its box). The bound is rigorous up to rounding;
/// it overestimates the actual error by orders of magnitude, so decisions that must be certain
/// escalate beta until the bound allows them (decide()).
///
/// Works in double precision on the points it is given; thread-safe const queries; the same
/// query gives the same bits on any thread (a fixed traversal order).
class WindingNumberField {
 public:
  static constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();

  /// Builds the hierarchy and the expansions (parallel, deterministic). Triangles with repeated
  /// corners or zero area contribute nothing. Keeps references to both vectors, which must
  /// outlive the field and stay unchanged.
  WindingNumberField(const std::vector<Eigen::Vector3d>& points,
                     const std::vector<TriangleIndices>& triangles);

  /// An approximate value and a bound on |value - w(q)|.
  struct Estimate {
    double value = 0.0;
    double errorBound = 0.0;
  };

  /// Hierarchical evaluation with admissibility |q - centre| > beta * radius (beta > 1);
  /// `excluded` (if any) is left out of the sum, e.g. to evaluate at a point of that triangle.
  Estimate estimate(const Eigen::Vector3d& q, double beta,
                    std::uint32_t excluded = kNoTriangle) const;

  /// The exact sum over every triangle (but `excluded`), in triangle order.
  double exact(const Eigen::Vector3d& q, std::uint32_t excluded = kNoTriangle) const;

  /// Evaluates with beta = 3, 6, 12, 24 until `certain(estimate)` holds, then exactly (the
  /// exact value is returned whatever `certain` says of it). Returns the last value.
  double decide(const Eigen::Vector3d& q, const std::function<bool(const Estimate&)>& certain,
                std::uint32_t excluded = kNoTriangle) const;

  /// An upper bound of |w(q)| over every q of the box [low, high]: a triangle at distance D
  /// from q subtends a solid angle of at most its area over D^2, summed over the hierarchy's
  /// nodes (opened while that is coarse, and down to single triangles; box distances). Infinity
  /// when a triangle touches the box; stops early, returning a value above `limit`, once the sum
  /// exceeds `limit`.
  double boundOverBox(const Eigen::Vector3d& low, const Eigen::Vector3d& high, double limit) const;

  /// w(q) rounded to the nearest integer, certified (for closed, consistently oriented meshes).
  long integerValue(const Eigen::Vector3d& q) const;
  /// Whether w(q) >= 1/2, certified.
  bool atLeastHalf(const Eigen::Vector3d& q) const;

  const TriangleBvh& hierarchy() const { return bvh_; }

 private:
  /// Second-order expansion of a node about its centre c: with d = x - c and unit normal n,
  /// m0 = int n dA, m1(j, i) = int d_j n_i dA, m2[i](j, k) = int d_j d_k n_i dA.
  struct Expansion {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    double radius = 0.0;  ///< every triangle corner of the node lies within it of the centre
    double area = 0.0;    ///< unsigned
    Eigen::Vector3d m0 = Eigen::Vector3d::Zero();
    Eigen::Matrix3d m1 = Eigen::Matrix3d::Zero();
    std::array<Eigen::Matrix3d, 3> m2{Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero(),
                                      Eigen::Matrix3d::Zero()};
  };
  void buildExpansion(std::uint32_t nodeIndex);
  double triangleSolidAngle(std::uint32_t triangle, const Eigen::Vector3d& q) const;

  const std::vector<Eigen::Vector3d>& points_;
  const std::vector<TriangleIndices>& triangles_;
  TriangleBvh bvh_;
  std::vector<Expansion> expansions_;
};

}  // namespace d2vdb::detail
