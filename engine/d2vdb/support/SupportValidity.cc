#include "d2vdb/support/SupportValidity.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

RadiusSigns classify(double radius1, double radius2) {
  if (radius1 > 0.0) return RadiusSigns::Convex;
  if (radius2 < 0.0) return RadiusSigns::Concave;
  if (radius1 < 0.0 && radius2 > 0.0) return RadiusSigns::Saddle;
  return RadiusSigns::Parabolic;
}

// Six significant digits: enough to read a radius or a range in a message.
std::string shortNumber(double value) {
  return formatNumber(value, 6);
}

// Unit vector at angle t from n along the unit tangent e.
Eigen::Vector3d alongGreatCircle(const Eigen::Vector3d& n, const Eigen::Vector3d& e, double t) {
  return (std::cos(t) * n + std::sin(t) * e).normalized();
}

// Local minimum of `objective` on the sphere near `start` by compass search: eight directions in
// the tangent plane, the step halved whenever none improves, down to 1e-9 rad.
template <typename Objective>
Eigen::Vector3d polishMinimum(const Objective& objective, const Eigen::Vector3d& start,
                              double initialStep, double& best) {
  Eigen::Vector3d current = start;
  best = objective(current);
  double step = initialStep;
  for (int iteration = 0; iteration < 400 && step > 1e-9; ++iteration) {
    const Eigen::Vector3d e1 = current.unitOrthogonal();
    const Eigen::Vector3d e2 = current.cross(e1);
    Eigen::Vector3d candidate = current;
    double candidateValue = best;
    for (int k = 0; k < 8; ++k) {
      const double angle = k * 0.78539816339744831;
      const Eigen::Vector3d direction = std::cos(angle) * e1 + std::sin(angle) * e2;
      const Eigen::Vector3d n = alongGreatCircle(current, direction, step);
      const double value = objective(n);
      if (value < candidateValue) {
        candidateValue = value;
        candidate = n;
      }
    }
    if (candidateValue < best) {
      best = candidateValue;
      current = candidate;
    } else {
      step *= 0.5;
    }
  }
  return current;
}

/// The normals the radii are sampled at: every vertex of `domain`, plus, for a domain that does
/// not cover the whole sphere, three points inside each triangle. `spacing` becomes the longest
/// edge (radians).
std::vector<Eigen::Vector3d> sampleNormals(const SphericalTriangulation& domain, bool whole,
                                           double& spacing) {
  std::vector<Eigen::Vector3d> normals = domain.normals;
  spacing = 0.0;
  for (const auto& tri : domain.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& a = domain.normals[tri[static_cast<std::size_t>(k)]];
      const Eigen::Vector3d& b = domain.normals[tri[static_cast<std::size_t>((k + 1) % 3)]];
      spacing = std::max(spacing, std::atan2(a.cross(b).norm(), a.dot(b)));
    }
    if (!whole) {
      // Points inside the spherical triangle (barycentric (2,1,1)/4 and permutations).
      const Eigen::Vector3d& a = domain.normals[tri[0]];
      const Eigen::Vector3d& b = domain.normals[tri[1]];
      const Eigen::Vector3d& c = domain.normals[tri[2]];
      normals.push_back((2 * a + b + c).normalized());
      normals.push_back((a + 2 * b + c).normalized());
      normals.push_back((a + b + 2 * c).normalized());
    }
  }
  return normals;
}

/// The sign pattern at every sampled point, counted by pattern in `v` with the radius range.
std::vector<RadiusSigns> tallySigns(const std::vector<SupportPoint>& points, SupportValidity& v) {
  v.normalsChecked = points.size();
  v.minRadius = kInfinity;
  v.maxRadius = -kInfinity;
  std::vector<RadiusSigns> signs(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SupportPoint& p = points[i];
    v.minRadius = std::min(v.minRadius, p.radius1);
    v.maxRadius = std::max(v.maxRadius, p.radius2);
    signs[i] = classify(p.radius1, p.radius2);
    switch (signs[i]) {
      case RadiusSigns::Convex:
        ++v.convexNormals;
        break;
      case RadiusSigns::Saddle:
        ++v.saddleNormals;
        break;
      case RadiusSigns::Concave:
        ++v.concaveNormals;
        break;
      default:
        ++v.parabolicNormals;
        break;
    }
  }
  return signs;
}

/// Parabolic crossings along the domain's edges (in edge order), each located by bisection of
/// the sign pattern; `signs` are those of the domain's vertices (and more).
void locateParabolicCrossings(const SupportFunction& h, const SphericalTriangulation& domain,
                              const std::vector<RadiusSigns>& signs, SupportValidity& v) {
  std::map<std::pair<SphericalTriangulation::Index, SphericalTriangulation::Index>, bool> edges;
  for (const auto& tri : domain.triangles) {
    for (int k = 0; k < 3; ++k) {
      edges.emplace(
          std::minmax(tri[static_cast<std::size_t>(k)], tri[static_cast<std::size_t>((k + 1) % 3)]),
          true);
    }
  }
  for (const auto& edge : edges) {
    const auto a = edge.first.first;
    const auto b = edge.first.second;
    if (signs[a] == signs[b]) continue;
    ++v.parabolicCrossings;
    if (v.parabolicPoints.size() >= kMaxParabolicPoints) continue;
    Eigen::Vector3d lo = domain.normals[a];
    Eigen::Vector3d hi = domain.normals[b];
    const RadiusSigns loSigns = signs[a];
    for (int iteration = 0; iteration < 24; ++iteration) {
      const Eigen::Vector3d mid = (lo + hi).normalized();
      const SupportPoint p = h.evaluate(mid);
      if (classify(p.radius1, p.radius2) == loSigns) {
        lo = mid;
      } else {
        hi = mid;
      }
    }
    v.parabolicPoints.push_back((lo + hi).normalized());
  }
}

/// The smallest value of `radius` over the sampled points (`value`) and where it is (`where`),
/// polished by compass search from there when the domain is the whole sphere.
template <typename Radius>
void smallestRadius(const SupportFunction& h, const std::vector<SupportPoint>& points, bool whole,
                    double spacing, const Radius& radius, double& value, Eigen::Vector3d& where) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    if (radius(points[i]) < radius(points[best])) best = i;
  }
  value = radius(points[best]);
  where = points[best].normal;
  if (whole) {
    where = polishMinimum([&](const Eigen::Vector3d& n) { return radius(h.evaluate(n)); }, where,
                          spacing, value);
  }
}

/// The safe offset range of a regular domain (v.signs set): limited below by the smallest
/// positive radius and above by the smallest |negative| one.
void findSafeOffsets(const SupportFunction& h, const std::vector<SupportPoint>& points, bool whole,
                     double spacing, SupportValidity& v) {
  const auto positiveRadius = [&](const SupportPoint& p) {
    return v.signs == RadiusSigns::Convex ? p.radius1 : p.radius2;
  };
  const auto negativeMagnitude = [&](const SupportPoint& p) {
    return v.signs == RadiusSigns::Concave ? -p.radius2 : -p.radius1;
  };
  v.safeOffsetMin = -kInfinity;
  v.safeOffsetMax = kInfinity;
  if (v.signs != RadiusSigns::Concave) {
    double value = 0.0;
    smallestRadius(h, points, whole, spacing, positiveRadius, value, v.safeOffsetMinNormal);
    v.safeOffsetMin = -value;
  }
  if (v.signs != RadiusSigns::Convex) {
    double value = 0.0;
    smallestRadius(h, points, whole, spacing, negativeMagnitude, value, v.safeOffsetMaxNormal);
    v.safeOffsetMax = value;
  }
  // The polished extremes refine the sampled radius range.
  if (v.signs == RadiusSigns::Convex) v.minRadius = std::min(v.minRadius, -v.safeOffsetMin);
  if (v.signs == RadiusSigns::Concave) v.maxRadius = std::max(v.maxRadius, -v.safeOffsetMax);
}

}  // namespace

const char* radiusSignsName(RadiusSigns signs) {
  switch (signs) {
    case RadiusSigns::Convex:
      return "convex";
    case RadiusSigns::Saddle:
      return "saddle";
    case RadiusSigns::Concave:
      return "concave";
    default:
      return "parabolic";
  }
}

std::string SupportValidity::describe() const {
  std::string text;
  if (regular()) {
    text = std::string("regular, ") + radiusSignsName(signs) + ": radii " + shortNumber(minRadius) +
           " .. " + shortNumber(maxRadius) + ", safe offsets (" + shortNumber(safeOffsetMin) +
           ", " + shortNumber(safeOffsetMax) + ")";
  } else {
    text = "singular: " + std::to_string(parabolicCrossings) +
           " crossings of the parabolic set (det(Hess_S h + h I) = 0) on " +
           std::to_string(normalsChecked) + " sampled normals (" + std::to_string(convexNormals) +
           " convex, " + std::to_string(saddleNormals) + " saddle, " +
           std::to_string(concaveNormals) + " concave, " + std::to_string(parabolicNormals) +
           " parabolic), radii " + shortNumber(minRadius) + " .. " + shortNumber(maxRadius);
  }
  return text;
}

SphericalTriangulation validationSphere(int degree) {
  const double spacing = 0.5 / std::max(degree, 1);
  return geodesicSphere(std::clamp(geodesicSubdivisionsForSpacing(spacing), 2, 9));
}

SupportValidity analyzeSupportValidity(const SupportFunction& h, SphericalTriangulation domain) {
  validateSphericalTriangulation(domain, "the support function's domain");
  const bool whole = coversWholeSphere(domain);
  double spacing = 0.0;
  const std::vector<SupportPoint> points = h.evaluate(sampleNormals(domain, whole, spacing));
  SupportValidity v;
  const std::vector<RadiusSigns> signs = tallySigns(points, v);
  locateParabolicCrossings(h, domain, signs, v);
  if (!v.regular()) {
    v.safeOffsetMin = std::numeric_limits<double>::quiet_NaN();
    v.safeOffsetMax = std::numeric_limits<double>::quiet_NaN();
    return v;
  }
  v.signs = signs.empty() ? RadiusSigns::Convex : signs.front();
  findSafeOffsets(h, points, whole, spacing, v);
  return v;
}

void requireRegularOffset(const SupportValidity& validity, double distance) {
  if (!std::isfinite(distance)) throw InputError("the offset distance is not finite");
  if (!validity.regular()) {
    throw InputError("the support function is " + validity.describe() +
                     ": its surface x_h has cusps or edges where the radii change sign, so no "
                     "offset of it is a regular surface");
  }
  // The offset's principal radius R + distance at the normal where the radius R = -bound.
  const auto refuse = [&](double bound, const Eigen::Vector3d& normal, const char* relation) {
    throw InputError("offset distance " + shortNumber(distance) + " is outside the safe range (" +
                     shortNumber(validity.safeOffsetMin) + ", " +
                     shortNumber(validity.safeOffsetMax) + "): at the normal " +
                     formatPoint(normal, 6) + " the principal radius " + shortNumber(-bound) +
                     " would become " + shortNumber(distance - bound) + " " + relation +
                     " 0, so the offset surface would have a cusp and fold over itself");
  };
  if (distance <= validity.safeOffsetMin) {
    refuse(validity.safeOffsetMin, validity.safeOffsetMinNormal, "<=");
  }
  if (distance >= validity.safeOffsetMax) {
    refuse(validity.safeOffsetMax, validity.safeOffsetMaxNormal, ">=");
  }
}

}  // namespace d2vdb
