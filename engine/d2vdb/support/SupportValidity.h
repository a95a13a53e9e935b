// Where a support-function surface is regular, and which offsets keep it so (Sir, Gravesen,
// Juettler, "Curves and surfaces represented by polynomial support functions", 2008, Theorem 1
// and section 5).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

#include "d2vdb/support/SphericalTriangulation.h"
#include "d2vdb/support/SupportFunction.h"

namespace d2vdb {

/// The sign pattern of the principal radii (radius1 <= radius2) at a normal.
enum class RadiusSigns {
  Convex,     ///< both positive: the surface bends away from its normal (a convex body's boundary)
  Saddle,     ///< radius1 < 0 < radius2: hyperbolic point
  Concave,    ///< both negative
  Parabolic,  ///< a radius is zero: x_h is singular there
};

/// Name of a sign pattern: "convex", "saddle", "concave", "parabolic".
const char* radiusSignsName(RadiusSigns signs);

/// What analyzeSupportValidity() found on a domain.
struct SupportValidity {
  std::size_t normalsChecked = 0;
  double minRadius = 0.0;  ///< smallest radius1 over the checked normals
  double maxRadius = 0.0;  ///< largest radius2
  std::size_t convexNormals = 0;
  std::size_t saddleNormals = 0;
  std::size_t concaveNormals = 0;
  std::size_t parabolicNormals = 0;  ///< a radius exactly zero
  /// The parabolic set det(Hess_S h + h I) = 0 met on the domain: one point (a unit normal,
  /// located by bisection to about 1e-6 rad) on every sampled edge whose ends have different sign
  /// patterns. Stored up to kMaxParabolicPoints; parabolicCrossings counts them all.
  std::vector<Eigen::Vector3d> parabolicPoints;
  std::size_t parabolicCrossings = 0;
  /// The sign pattern of a regular domain (meaningless when !regular()).
  RadiusSigns signs = RadiusSigns::Convex;
  /// The open interval of offsets d for which h + d stays regular on the domain: radius + d keeps
  /// its sign for every radius, i.e. d > -(smallest positive radius) and d < (smallest |negative
  /// radius|); -inf / +inf where no radius of that sign exists. Only meaningful when regular().
  /// Local regularity only: offsets of a non-convex patch may still intersect themselves
  /// globally.
  double safeOffsetMin = 0.0;
  double safeOffsetMax = 0.0;
  Eigen::Vector3d safeOffsetMinNormal = Eigen::Vector3d::Zero();  ///< where the lower limit is
  Eigen::Vector3d safeOffsetMaxNormal = Eigen::Vector3d::Zero();  ///< where the upper limit is

  /// One sign pattern everywhere and no parabolic point: x_h is a regular surface over the
  /// domain (to the sampling step).
  bool regular() const {
    return parabolicCrossings == 0 && parabolicNormals == 0 &&
           (convexNormals == normalsChecked || saddleNormals == normalsChecked ||
            concaveNormals == normalsChecked);
  }
  /// A one-line summary ("regular, convex: radii 0.25 .. 4, safe offsets (-0.25, inf)" or
  /// "singular: 312 parabolic crossings, ...").
  std::string describe() const;
};

/// Stored parabolic points are capped at this many.
inline constexpr std::size_t kMaxParabolicPoints = 100000;

/// Samples the principal radii of h over `domain`: every vertex, plus (for domains that do not
/// cover the whole sphere) extra points inside each triangle, so the sampling stays inside the
/// patch. On the whole sphere the extreme radii are then refined by a local search from the best
/// sample (the surface is analytic, so this gives the true extreme, not just the best vertex).
/// Use a domain at least as fine as geodesicSphere(geodesicSubdivisionsForSpacing(0.5 / L)).
/// Evaluation is parallel and deterministic. Throws InputError for an invalid domain.
SupportValidity analyzeSupportValidity(const SupportFunction& h, SphericalTriangulation domain);

/// The geodesic sphere used to check a support function of degree `degree` over the whole sphere:
/// spacing at most 0.5 / max(degree, 1) radians (between 2 and 9 subdivisions).
SphericalTriangulation validationSphere(int degree);

/// Throws InputError unless the offset surface at distance `distance` is regular: the validity
/// must be regular() and the distance inside (safeOffsetMin, safeOffsetMax). The message names
/// the distance, the safe range and what limits it (the smallest radius and where), or the
/// parabolic set, and points to `--allow-singular`.
void requireRegularOffset(const SupportValidity& validity, double distance);

}  // namespace d2vdb
