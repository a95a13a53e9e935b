#include "d2vdb/measure/detail/CertifiedDistance.h"

namespace d2vdb::detail {
namespace {

// The parameter in [0, 1] of the point of the segment from -> to nearest to p (0 for a segment of
// length 0).
double segmentParameter(const Eigen::Vector3d& p, const Eigen::Vector3d& from,
                        const Eigen::Vector3d& to) {
  const Eigen::Vector3d along = to - from;
  const double length2 = along.squaredNorm();
  return length2 > 0.0 ? std::clamp((p - from).dot(along) / length2, 0.0, 1.0) : 0.0;
}

// A flat triangle (collinear or coincident corners): the nearest of its three sides.
TriangleCoordinates nearestSide(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double onAb = segmentParameter(p, a, b);
  const double onBc = segmentParameter(p, b, c);
  const double onCa = segmentParameter(p, c, a);
  const TriangleCoordinates candidates[3] = {{onAb, 0.0}, {1.0 - onBc, onBc}, {0.0, 1.0 - onCa}};
  const Eigen::Vector3d points[3] = {a + onAb * (b - a), b + onBc * (c - b), c + onCa * (a - c)};
  int best = 0;
  for (int side = 1; side < 3; ++side) {
    if ((points[side] - p).squaredNorm() < (points[best] - p).squaredNorm()) best = side;
  }
  return candidates[best];
}

// Ericson's Voronoi-region tests, returning coordinates instead of the point.
TriangleCoordinates voronoiCoordinates(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {0.0, 0.0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return {d1 / (d1 - d3), 0.0};
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return {0.0, d2 / (d2 - d6)};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {1.0 - t, t};
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return nearestSide(p, a, b, c);
  return {vb / sum, vc / sum};
}

}  // namespace

TriangleCoordinates closestTriangleCoordinates(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                               const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  TriangleCoordinates coordinates = voronoiCoordinates(p, a, b, c);
  // NaN-safe clamps: a NaN coordinate becomes 0.
  coordinates.beta = coordinates.beta > 0.0 ? std::min(coordinates.beta, 1.0) : 0.0;
  const double room = 1.0 - coordinates.beta;
  coordinates.gamma = coordinates.gamma > 0.0 ? std::min(coordinates.gamma, room) : 0.0;
  return coordinates;
}

}  // namespace d2vdb::detail
