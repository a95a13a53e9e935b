// Local quadratic approximants of the squared distance function (Pottmann and Hofer, "Geometry of
// the squared distance function to curves and surfaces", 2003; engine/README.md) and the PDM / TDM
// / SDM quadratic forms the fitting solvers minimise. Eigen only: no OpenVDB, so fitters and tests
// include it cheaply.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>

namespace d2vdb {

/// What an approximant's target is.
enum class TargetKind : std::uint8_t {
  Surface = 0,  ///< a closed surface (signed distance, d < 0 inside)
  Curve = 1,    ///< a curve in 3D, planar curves included (unsigned distance, codimension 2)
  Points = 2,   ///< a point set (unsigned distance; the approximant is |x - q|^2)
};

/// Name of a target kind: "surface", "curve", "points".
const char* targetKindName(TargetKind kind);

/// The error term of a fitting method (engine/README.md, "The squared-distance approximant").
enum class ErrorTerm : std::uint8_t {
  PDM = 0,  ///< point distance: |x - s|^2
  TDM = 1,  ///< tangent distance: squared distance to the tangent plane (surface) or tangent line
            ///< (curve) at the footpoint s; |x - s|^2 for point sets, which have no tangent
  SDM = 2,  ///< squared distance: the second-order Taylor approximant with clamped weights
};

/// Name of an error term: "pdm", "tdm", "sdm".
const char* errorTermName(ErrorTerm term);

/// A quadratic function of a world point, Q(x) = x^T A x - 2 b.x + c (world units squared), with
/// A symmetric positive semidefinite for every form an Approximant returns. For those forms
/// A = sum_i w_i e_i e_i^T in an orthonormal frame and b = A s, c = s^T A s with s the footpoint,
/// so Q(x) = (x - s)^T A (x - s) >= 0.
struct QuadraticForm {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double c = 0.0;

  /// Q(x).
  double operator()(const Eigen::Vector3d& x) const { return x.dot(A * x) - 2.0 * b.dot(x) + c; }
  /// grad Q(x) = 2 (A x - b).
  Eigen::Vector3d gradient(const Eigen::Vector3d& x) const { return 2.0 * (A * x - b); }
  /// The (constant) Hessian 2 A.
  Eigen::Matrix3d hessian() const { return 2.0 * A; }
};

/// Bits of Approximant::flags.
enum ApproximantFlag : std::uint16_t {
  /// Near the cut locus (medial axis) or past a centre of curvature: the footpoint is ambiguous
  /// or 1 + d k_i is not safely positive. Curvature weights are clamped (the SDM form falls back
  /// toward TDM there); all values stay finite.
  kFlagCutLocus = 1u << 0,
  /// A principal curvature exceeded what the grid resolves (|k| > 1 / voxel size) and was clamped.
  kFlagCurvatureClamped = 1u << 1,
  /// The curvature estimate used an incomplete stencil (a band narrower than the estimator needs,
  /// a thin feature); footpoint and normal are still valid.
  kFlagDegradedEstimate = 1u << 2,
  /// Answered by a coarse level of the field, beyond the narrow band (error bound:
  /// ApproximantField.h).
  kFlagFarField = 1u << 3,
  /// The footpoint is an end point of an open curve (or a corner of a polyline), or lies on the
  /// boundary of an open surface: the distance there is to a point, so the SDM and TDM forms are
  /// the PDM form.
  kFlagEndPoint = 1u << 4,
};

/// The data of one local quadratic approximant of the squared distance d^2 to a target, taken at
/// the point `origin` (a voxel centre of a field, or the query point of an exact target).
///
/// Frame: (tangent, bitangent(), normal) is a right-handed orthonormal frame at the footpoint.
/// - Surface: `normal` is the outward unit normal at the footpoint, `tangent` the first principal
///   direction e1, bitangent() = normal x e1 = e2; k1, k2 are the principal curvatures along e1,
///   e2 (1 / world units, positive where the surface bends away from the normal: a sphere of
///   radius R has k = 1/R); distance is signed (negative inside), origin = footpoint +
///   distance * normal.
/// - Curve: `tangent` is the unit tangent at the footpoint, `normal` the unit vector from the
///   footpoint toward origin (any unit vector orthogonal to the tangent when distance is 0), k1 the
///   curvature kappa >= 0 and principalNormal the unit principal normal N (zero when kappa = 0);
///   distance >= 0, origin = footpoint + distance * normal.
/// - Points: footpoint is the nearest point q, `normal` the unit vector from q toward origin,
///   `tangent` any unit vector orthogonal to it; distance = |origin - q| >= 0.
struct Approximant {
  TargetKind kind = TargetKind::Surface;
  std::uint16_t flags = 0;                                    ///< ApproximantFlag bits
  double distance = 0.0;                                      ///< world units, at origin
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();           ///< where the data was taken (world)
  Eigen::Vector3d footpoint = Eigen::Vector3d::Zero();        ///< closest target point of origin
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();          ///< see the frame above
  Eigen::Vector3d tangent = Eigen::Vector3d::UnitX();         ///< see the frame above
  double k1 = 0.0;                                            ///< 1 / world units
  double k2 = 0.0;                                            ///< surfaces only
  Eigen::Vector3d principalNormal = Eigen::Vector3d::Zero();  ///< curves only

  /// normal x tangent: e2 for surfaces, the second normal-plane axis for curves.
  Eigen::Vector3d bitangent() const { return normal.cross(tangent); }

  /// The normal curvature that governs the tangential SDM weight along the tangent: k1 for
  /// surfaces; for curves -kappa (N . normal), the curvature of the curve seen from origin
  /// (positive when the curve bends away from origin).
  double tangentCurvature() const;

  /// The SDM weights (w_tangent, w_bitangent, w_normal) (engine/README.md):
  /// w_i = max(0, d k_i / (1 + d k_i)) = max(0, d / (d - rho_i)) with rho_i = -1 / k_i, for the
  /// curvatures along tangent and bitangent (surfaces: k1, k2; curves: tangentCurvature() and 0,
  /// i.e. weight 1 in the whole normal plane; points: 1, 1, 1), and 1 along the normal. Where
  /// 1 + d k_i <= 1e-3 (at or past a centre of curvature) the weight is 0. Open-curve end points
  /// (kFlagEndPoint) get 1, 1, 1. Every weight lies in [0, 1].
  Eigen::Vector3d sdmWeights() const;

  /// The weights of `term` in the frame (tangent, bitangent, normal): PDM (1, 1, 1); TDM surface
  /// (0, 0, 1), curve (0, 1, 1), points and end points (1, 1, 1); SDM sdmWeights().
  Eigen::Vector3d weights(ErrorTerm term) const;

  /// The quadratic form of `term`: Q(x) = sum_i w_i ((x - footpoint) . f_i)^2 over the frame
  /// vectors f_i with weights(term). World coordinates and units squared.
  QuadraticForm form(ErrorTerm term) const;
};

}  // namespace d2vdb
