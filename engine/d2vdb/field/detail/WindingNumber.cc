#include "d2vdb/field/detail/WindingNumber.h"
#include "d2vdb/core/MathConstants.h"

#include <tbb/task_group.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace d2vdb::detail {
namespace {

constexpr double kFourPi = 4.0 * 3.14159265358979323846;
/// Rounding in the exact sums and the moments, well above double precision for the sums of the
/// meshes d2vdb handles (at most ~1e8 triangles) and far below any decision margin.
constexpr double kRoundingSlack = 1e-9;
/// Subtrees with fewer nodes than this get their expansions from the calling task.
constexpr std::uint32_t kSerialNodes = 2048;

double distanceToBox(const Eigen::Vector3d& q, const TriangleBvh::Node& node) {
  const Eigen::Vector3d outside =
      (node.low - q).cwiseMax(q - node.high).cwiseMax(Eigen::Vector3d::Zero());
  return outside.norm();
}

/// Area of the triangle abc.
double areaOf(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

/// Distance between two axis-aligned boxes (0 when they overlap).
double boxDistance(const Eigen::Vector3d& lowA, const Eigen::Vector3d& highA,
                   const Eigen::Vector3d& lowB, const Eigen::Vector3d& highB) {
  const Eigen::Vector3d gap =
      (lowB - highA).cwiseMax(lowA - highB).cwiseMax(Eigen::Vector3d::Zero());
  return gap.norm();
}

}  // namespace

double solidAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double la = a.norm();
  const double lb = b.norm();
  const double lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2.0 * std::atan2(numerator, denominator);
}

WindingNumberField::WindingNumberField(const std::vector<Eigen::Vector3d>& points,
                                       const std::vector<TriangleIndices>& triangles)
    : points_(points),
      triangles_(triangles),
      bvh_(points_, triangles_),
      expansions_(bvh_.nodes().size()) {
  if (!expansions_.empty()) buildExpansion(0);
}

void WindingNumberField::buildExpansion(std::uint32_t nodeIndex) {
  const TriangleBvh::Node& node = bvh_.nodes()[nodeIndex];
  Expansion& expansion = expansions_[nodeIndex];
  if (node.isLeaf()) {
    // Vector areas N = A n, centroids g; the centre is the area-weighted centroid.
    double area = 0.0;
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
    for (std::uint32_t i = node.begin; i < node.end; ++i) {
      const auto [a, b, c] = cornersOf(points_, triangles_[bvh_.order()[i]]);
      const double triangleArea = areaOf(a, b, c);
      area += triangleArea;
      weighted += triangleArea * (a + b + c) / 3.0;
    }
    expansion.area = area;
    expansion.center = area > 0.0 ? Eigen::Vector3d(weighted / area)
                                  : Eigen::Vector3d(0.5 * (node.low + node.high));
    const Eigen::Vector3d& center = expansion.center;
    for (std::uint32_t i = node.begin; i < node.end; ++i) {
      const TriangleIndices& tri = triangles_[bvh_.order()[i]];
      const Eigen::Vector3d da = points_[tri[0]] - center;
      const Eigen::Vector3d db = points_[tri[1]] - center;
      const Eigen::Vector3d dc = points_[tri[2]] - center;
      expansion.radius = std::max({expansion.radius, da.norm(), db.norm(), dc.norm()});
      const Eigen::Vector3d vectorArea = 0.5 * (db - da).cross(dc - da);
      const Eigen::Vector3d centroid = (da + db + dc) / 3.0;
      expansion.m0 += vectorArea;
      expansion.m1 += centroid * vectorArea.transpose();
      // int over the triangle of d d^T dA = A / 12 (sum of corner outer products + s s^T) with
      // s the sum of the corners; times n_i gives the factor N_i / 12.
      const Eigen::Vector3d sum = da + db + dc;
      const Eigen::Matrix3d second =
          da * da.transpose() + db * db.transpose() + dc * dc.transpose() + sum * sum.transpose();
      for (int axis = 0; axis < 3; ++axis) {
        expansion.m2[axis] += (vectorArea[axis] / 12.0) * second;
      }
    }
    return;
  }
  const std::uint32_t left = nodeIndex + 1;
  const std::uint32_t right = node.right;
  if (node.end - node.begin >= kSerialNodes * bvh_.leafSize()) {
    tbb::task_group group;
    group.run([&] { buildExpansion(left); });
    buildExpansion(right);
    group.wait();
  } else {
    buildExpansion(left);
    buildExpansion(right);
  }
  const Expansion& l = expansions_[left];
  const Expansion& r = expansions_[right];
  expansion.area = l.area + r.area;
  expansion.center = expansion.area > 0.0
                         ? Eigen::Vector3d((l.area * l.center + r.area * r.center) / expansion.area)
                         : Eigen::Vector3d(0.5 * (node.low + node.high));
  const Eigen::Vector3d& center = expansion.center;
  // Radius: the smaller of two upper bounds (through the children's spheres, through the box).
  const double throughChildren =
      std::max((l.center - center).norm() + l.radius, (r.center - center).norm() + r.radius);
  const Eigen::Vector3d farCorner =
      (node.high - center).cwiseAbs().cwiseMax((node.low - center).cwiseAbs());
  expansion.radius = std::min(throughChildren, farCorner.norm());
  // Moments moved to the new centre: with s = c_child - c, d = d_child + s.
  for (const Expansion* child : {&l, &r}) {
    const Eigen::Vector3d s = child->center - center;
    expansion.m0 += child->m0;
    expansion.m1 += child->m1 + s * child->m0.transpose();
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d column = child->m1.col(axis);  // (int d_j n_axis dA)_j
      expansion.m2[axis] += child->m2[axis] + s * column.transpose() + column * s.transpose() +
                            (child->m0[axis] * s) * s.transpose();
    }
  }
}

double WindingNumberField::triangleSolidAngle(std::uint32_t triangle,
                                              const Eigen::Vector3d& q) const {
  const TriangleIndices& tri = triangles_[triangle];
  if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) return 0.0;
  const Eigen::Vector3d a = points_[tri[0]] - q;
  const Eigen::Vector3d b = points_[tri[1]] - q;
  const Eigen::Vector3d c = points_[tri[2]] - q;
  if ((b - a).cross(c - a).squaredNorm() == 0.0) return 0.0;
  return solidAngle(a, b, c);
}

WindingNumberField::Estimate WindingNumberField::estimate(const Eigen::Vector3d& q, double beta,
                                                          std::uint32_t excluded) const {
  Estimate result;
  if (bvh_.nodes().empty()) return result;
  double angles = 0.0;    // exact solid angles of opened leaves
  double farField = 0.0;  // expansions, already divided by 4 pi
  double bound = 0.0;
  // The left subtree is summed before the right one.
  walkDepthFirst(bvh_, [&](std::uint32_t index, const TriangleBvh::Node& node) {
    const Expansion& expansion = expansions_[index];
    const Eigen::Vector3d y = expansion.center - q;
    const double distance2 = y.squaredNorm();
    const double radius = expansion.radius;
    if (distance2 > beta * beta * radius * radius) {
      if (expansion.area == 0.0) return BvhStep::kSkip;
      const double distance = std::sqrt(distance2);
      const double inverse = 1.0 / distance;
      const double inverse3 = inverse * inverse * inverse;
      const double inverse5 = inverse3 * inverse * inverse;
      const double inverse7 = inverse5 * inverse * inverse;
      const double term0 = y.dot(expansion.m0) * inverse3;
      const double term1 =
          expansion.m1.trace() * inverse3 - 3.0 * y.dot(expansion.m1 * y) * inverse5;
      double s1 = 0.0, s2 = 0.0, s3 = 0.0;
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d my = expansion.m2[i] * y;
        s1 += my[i];
        s2 += y[i] * expansion.m2[i].trace();
        s3 += y[i] * y.dot(my);
      }
      const double term2 = 0.5 * (-3.0 * (2.0 * s1 + s2) * inverse5 + 15.0 * s3 * inverse7);
      farField += (term0 + term1 + term2) / kFourPi;
      const double rho = std::max(distance - radius, distanceToBox(q, node));
      const double rho2 = rho * rho;
      bound += expansion.area * radius * radius * radius / (kPi * rho2 * rho2 * rho);
      return BvhStep::kSkip;
    }
    if (!node.isLeaf()) return BvhStep::kChildren;
    for (std::uint32_t i = node.begin; i < node.end; ++i) {
      const std::uint32_t triangle = bvh_.order()[i];
      if (triangle != excluded) angles += triangleSolidAngle(triangle, q);
    }
    return BvhStep::kSkip;
  });
  result.value = angles / kFourPi + farField;
  result.errorBound = bound + kRoundingSlack;
  return result;
}

double WindingNumberField::exact(const Eigen::Vector3d& q, std::uint32_t excluded) const {
  double angles = 0.0;
  for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
    if (t != excluded) angles += triangleSolidAngle(t, q);
  }
  return angles / kFourPi;
}

double WindingNumberField::decide(const Eigen::Vector3d& q,
                                  const std::function<bool(const Estimate&)>& certain,
                                  std::uint32_t excluded) const {
  for (const double beta : {3.0, 6.0, 12.0, 24.0}) {
    const Estimate value = estimate(q, beta, excluded);
    if (certain(value)) return value.value;
  }
  return exact(q, excluded);
}

double WindingNumberField::boundOverBox(const Eigen::Vector3d& low, const Eigen::Vector3d& high,
                                        double limit) const {
  if (bvh_.nodes().empty()) return 0.0;
  // A node is summed whole once its share is below this fraction of the limit.
  const double fine = 1e-3 * limit;
  double bound = 0.0;
  walkDepthFirst(bvh_, [&](std::uint32_t index, const TriangleBvh::Node& node) {
    const double area = expansions_[index].area;
    if (area == 0.0) return BvhStep::kSkip;
    const double distance = boxDistance(low, high, node.low, node.high);
    const double share = distance > 0.0 ? area / (kFourPi * distance * distance)
                                        : std::numeric_limits<double>::infinity();
    if (share <= fine || (node.isLeaf() && node.end - node.begin == 1)) {
      bound += share;
    } else if (node.isLeaf()) {
      for (std::uint32_t i = node.begin; i < node.end; ++i) {
        const auto [a, b, c] = cornersOf(points_, triangles_[bvh_.order()[i]]);
        const double triangleArea = areaOf(a, b, c);
        if (triangleArea == 0.0) continue;
        const double d =
            boxDistance(low, high, a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c));
        bound +=
            d > 0.0 ? triangleArea / (kFourPi * d * d) : std::numeric_limits<double>::infinity();
      }
    } else {
      return BvhStep::kChildren;
    }
    // The rounding of the sum stays far below the slack added by the caller's decisions.
    return bound > limit ? BvhStep::kStop : BvhStep::kSkip;
  });
  if (bound > limit) return bound;
  return bound * (1.0 + 1e-12) + kRoundingSlack;
}

long WindingNumberField::integerValue(const Eigen::Vector3d& q) const {
  const double value = decide(q, [](const Estimate& e) {
    return std::abs(e.value - std::round(e.value)) + e.errorBound < 0.5;
  });
  return std::lround(value);
}

bool WindingNumberField::atLeastHalf(const Eigen::Vector3d& q) const {
  return decide(q, [](const Estimate& e) { return std::abs(e.value - 0.5) > e.errorBound; }) >= 0.5;
}

}  // namespace d2vdb::detail
