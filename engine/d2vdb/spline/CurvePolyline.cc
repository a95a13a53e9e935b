#include "d2vdb/spline/CurvePolyline.h"

#include <algorithm>
#include <cstddef>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

constexpr std::size_t kPointsPerSegment = 64;
constexpr std::size_t kMinimumPoints = 512;
constexpr std::size_t kMaximumPoints = 20000;

}  // namespace

int drawingPointCount(const BSplineCurve& curve) {
  const std::size_t segments = curve.toBezierSegments().size();
  return static_cast<int>(
      std::clamp<std::size_t>(kPointsPerSegment * segments, kMinimumPoints, kMaximumPoints));
}

std::vector<std::vector<Eigen::Vector3d>> drawingPolylines(
    std::initializer_list<std::reference_wrapper<const BSplineCurve>> curves) {
  int count = 0;
  for (const BSplineCurve& curve : curves) count = std::max(count, drawingPointCount(curve));
  std::vector<std::vector<Eigen::Vector3d>> polylines;
  polylines.reserve(curves.size());
  for (const BSplineCurve& curve : curves) polylines.push_back(curve.sample(count));
  return polylines;
}

double sampledLength(const BSplineCurve& curve, int samples) {
  if (samples < 2) {
    throw InputError("a sampled curve length needs at least 2 samples, got " +
                     std::to_string(samples));
  }
  const std::vector<Eigen::Vector3d> points = curve.sample(samples);
  double length = 0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

}  // namespace d2vdb
