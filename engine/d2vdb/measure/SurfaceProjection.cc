#include "d2vdb/measure/SurfaceProjection.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/spline/BasisFunctions.h"

namespace d2vdb {
namespace {

/// Position and first and second partial derivatives on one patch's polynomial piece.
/// Interleaves the bits of x and y (x in the even bits): the Morton code of a grid cell.
std::uint64_t mortonCode(std::uint32_t x, std::uint32_t y) {
  std::uint64_t code = 0;
  for (int bit = 0; bit < 32; ++bit) {
    code |= static_cast<std::uint64_t>((x >> bit) & 1u) << (2 * bit);
    code |= static_cast<std::uint64_t>((y >> bit) & 1u) << (2 * bit + 1);
  }
  return code;
}

void requireFiniteQuery(const Eigen::Vector3d& point) {
  if (!point.allFinite()) {
    throw InputError("surface projection: the query point is not finite");
  }
}

}  // namespace

SurfaceProjector::SurfaceProjector(const BSplineSurface& surface)
    : surface_(surface), patches_(toBezierPatches(surface)) {
  const int count = static_cast<int>(patches_.size());
  // Cell grid coordinates of the patches (u-major order) and their Morton order.
  int cellsV = 0;
  for (const BezierPatch& patch : patches_) {
    if (patch.spanU != patches_.front().spanU) break;
    ++cellsV;
  }
  std::vector<std::uint64_t> codes(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    codes[static_cast<std::size_t>(i)] =
        mortonCode(static_cast<std::uint32_t>(i / cellsV), static_cast<std::uint32_t>(i % cellsV));
  }
  patchOfLeaf_.resize(static_cast<std::size_t>(count));
  std::iota(patchOfLeaf_.begin(), patchOfLeaf_.end(), 0);
  std::sort(patchOfLeaf_.begin(), patchOfLeaf_.end(), [&](int a, int b) {
    return codes[static_cast<std::size_t>(a)] < codes[static_cast<std::size_t>(b)];
  });
  leafOfPatch_.resize(static_cast<std::size_t>(count));
  for (int leaf = 0; leaf < count; ++leaf) {
    leafOfPatch_[static_cast<std::size_t>(patchOfLeaf_[static_cast<std::size_t>(leaf)])] = leaf;
  }
  while (leafCount_ < count) leafCount_ *= 2;
  boxTree_.assign(static_cast<std::size_t>(2 * leafCount_), Eigen::AlignedBox3d());
  for (int leaf = 0; leaf < count; ++leaf) {
    Eigen::AlignedBox3d& box = boxTree_[static_cast<std::size_t>(leafCount_ + leaf)];
    for (const Eigen::Vector3d& point :
         patches_[static_cast<std::size_t>(patchOfLeaf_[static_cast<std::size_t>(leaf)])]
             .controlPoints) {
      box.extend(point);
    }
  }
  for (int node = leafCount_ - 1; node >= 1; --node) {
    boxTree_[static_cast<std::size_t>(node)] = boxTree_[static_cast<std::size_t>(2 * node)].merged(
        boxTree_[static_cast<std::size_t>(2 * node + 1)]);
  }
}

void SurfaceProjector::solveInPatch(int index, const Eigen::Vector3d& point, double u, double v,
                                    SurfaceFootpoint& best) const {
  const BezierPatch& patch = patches_[static_cast<std::size_t>(index)];
  const ParameterInterval iu = patch.intervalU;
  const ParameterInterval iv = patch.intervalV;
  u = std::clamp(u, iu.start, iu.end);
  v = std::clamp(v, iv.start, iv.end);
  SurfaceDerivatives d = surface_.derivativesInSpans(patch.spanU, patch.spanV, u, v);
  double value = (d.point - point).squaredNorm();
  for (int iteration = 0; iteration < 60; ++iteration) {
    const Eigen::Vector3d r = d.point - point;
    const double gu = r.dot(d.du);
    const double gv = r.dot(d.dv);
    // Bound constraints: a parameter at its bound whose gradient pushes outward stays there.
    const bool freeU = !((u <= iu.start && gu > 0.0) || (u >= iu.end && gu < 0.0));
    const bool freeV = !((v <= iv.start && gv > 0.0) || (v >= iv.end && gv < 0.0));
    if (!freeU && !freeV) break;
    const double euu = d.du.squaredNorm(), euv = d.du.dot(d.dv), evv = d.dv.squaredNorm();
    double huu = euu + r.dot(d.duu);
    double huv = euv + r.dot(d.duv);
    double hvv = evv + r.dot(d.dvv);
    double du = 0.0, dv = 0.0;
    if (freeU && freeV) {
      double det = huu * hvv - huv * huv;
      if (!(huu > 0.0) || !(det > 1e-12 * huu * hvv) || !(det > 0.0)) {
        // Not positive definite: Gauss-Newton (the first fundamental form), slightly damped.
        const double ridge = 1e-12 * (euu + evv) + std::numeric_limits<double>::min();
        huu = euu + ridge;
        huv = euv;
        hvv = evv + ridge;
        det = huu * hvv - huv * huv;
      }
      du = -(hvv * gu - huv * gv) / det;
      dv = -(huu * gv - huv * gu) / det;
    } else if (freeU) {
      du = -gu / (huu > 0.0 ? huu : euu + std::numeric_limits<double>::min());
    } else {
      dv = -gv / (hvv > 0.0 ? hvv : evv + std::numeric_limits<double>::min());
    }
    if (!std::isfinite(du) || !std::isfinite(dv)) break;
    // Backtracking on the true squared distance over the clamped step.
    double scale = 1.0;
    bool accepted = false;
    double nextU = u, nextV = v, nextValue = value;
    for (int halving = 0; halving < 40; ++halving, scale *= 0.5) {
      nextU = std::clamp(u + scale * du, iu.start, iu.end);
      nextV = std::clamp(v + scale * dv, iv.start, iv.end);
      nextValue =
          (surface_.evaluateInSpans(patch.spanU, patch.spanV, nextU, nextV) - point).squaredNorm();
      // Near the solution the decrease drops below the rounding of the squared distance (whose
      // error is about eps |S - p| (|S| + |p|)); the full step is then taken as long as it does not
      // increase it beyond that.
      const double slack = halving == 0
                               ? 16.0 * std::numeric_limits<double>::epsilon() *
                                     (value + std::sqrt(value) * (d.point.norm() + point.norm()))
                               : 0.0;
      if (nextValue <= value + slack) {
        accepted = true;
        break;
      }
    }
    if (!accepted) break;
    const double move = std::abs(nextU - u) / iu.length() + std::abs(nextV - v) / iv.length();
    u = nextU;
    v = nextV;
    value = nextValue;
    d = surface_.derivativesInSpans(patch.spanU, patch.spanV, u, v);
    value = (d.point - point).squaredNorm();
    if (move <= 1e-15) break;
  }
  if (value < best.squaredDistance) {
    best.u = u;
    best.v = v;
    best.point = d.point;
    best.squaredDistance = value;
    best.patch = index;
    const ParameterInterval domainU = surface_.domainU();
    const ParameterInterval domainV = surface_.domainV();
    best.onBoundary = (!surface_.isClosedU() && (u <= domainU.start || u >= domainU.end)) ||
                      (!surface_.isClosedV() && (v <= domainV.start || v >= domainV.end));
  }
}

void SurfaceProjector::visitPatch(int index, const Eigen::Vector3d& point,
                                  SurfaceFootpoint& best) const {
  const BezierPatch& patch = patches_[static_cast<std::size_t>(index)];
  // Start at the parameters of the nearest Bézier control point.
  const int q = patch.degreeV;
  int nearest = 0;
  double nearestDistance = std::numeric_limits<double>::infinity();
  for (int c = 0; c < static_cast<int>(patch.controlPoints.size()); ++c) {
    const double distance =
        (patch.controlPoints[static_cast<std::size_t>(c)] - point).squaredNorm();
    if (distance < nearestDistance) nearestDistance = distance, nearest = c;
  }
  const double s = patch.degreeU > 0 ? static_cast<double>(nearest / (q + 1)) / patch.degreeU : 0.5;
  const double t = q > 0 ? static_cast<double>(nearest % (q + 1)) / q : 0.5;
  solveInPatch(index, point, patch.intervalU.at(s), patch.intervalV.at(t), best);
}

SurfaceFootpoint SurfaceProjector::nearest(const Eigen::Vector3d& point,
                                           const SurfaceFootpoint* hint) const {
  requireFiniteQuery(point);
  SurfaceFootpoint best;
  int hinted = -1;
  if (hint != nullptr && hint->patch >= 0 && hint->patch < static_cast<int>(patches_.size()) &&
      std::isfinite(hint->u) && std::isfinite(hint->v)) {
    hinted = hint->patch;
    solveInPatch(hinted, point, hint->u, hint->v, best);
  }
  // Depth-first, nearer child first; a node is skipped when its box cannot beat the best.
  std::array<int, 128> stack{};
  int top = 0;
  stack[static_cast<std::size_t>(top++)] = 1;
  while (top > 0) {
    const int node = stack[static_cast<std::size_t>(--top)];
    const Eigen::AlignedBox3d& box = boxTree_[static_cast<std::size_t>(node)];
    if (box.isEmpty() || box.squaredExteriorDistance(point) >= best.squaredDistance) continue;
    if (node >= leafCount_) {
      const int patch = patchOfLeaf_[static_cast<std::size_t>(node - leafCount_)];
      if (patch != hinted) visitPatch(patch, point, best);
      continue;
    }
    const int left = 2 * node;
    const int right = 2 * node + 1;
    const double leftDistance =
        boxTree_[static_cast<std::size_t>(left)].isEmpty()
            ? std::numeric_limits<double>::infinity()
            : boxTree_[static_cast<std::size_t>(left)].squaredExteriorDistance(point);
    const double rightDistance =
        boxTree_[static_cast<std::size_t>(right)].isEmpty()
            ? std::numeric_limits<double>::infinity()
            : boxTree_[static_cast<std::size_t>(right)].squaredExteriorDistance(point);
    // Push the farther child first, so the nearer one is visited next.
    if (leftDistance <= rightDistance) {
      stack[static_cast<std::size_t>(top++)] = right;
      stack[static_cast<std::size_t>(top++)] = left;
    } else {
      stack[static_cast<std::size_t>(top++)] = left;
      stack[static_cast<std::size_t>(top++)] = right;
    }
  }
  return best;
}

std::vector<SurfaceFootpoint> SurfaceProjector::nearest(
    const std::vector<Eigen::Vector3d>& points, const std::vector<SurfaceFootpoint>& hints) const {
  if (!hints.empty() && hints.size() != points.size()) {
    throw InputError("surface projection: " + std::to_string(hints.size()) + " hints for " +
                     std::to_string(points.size()) + " points");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      throw InputError("surface projection: query point " + std::to_string(i) + " is not finite");
    }
  }
  std::vector<SurfaceFootpoint> result(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        result[i] = nearest(points[i], hints.empty() ? nullptr : &hints[i]);
                      }
                    });
  return result;
}

}  // namespace d2vdb
