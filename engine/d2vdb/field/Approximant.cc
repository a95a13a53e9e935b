// Quadratic forms of squared-distance approximants (Approximant.h).
#include "d2vdb/field/Approximant.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <limits>
#include <mutex>

#include "d2vdb/field/SquaredDistanceTarget.h"

namespace d2vdb {
namespace {

/// Smallest 1 + d k for which a curvature weight is trusted (at or past a centre of curvature the
/// Taylor expansion does not exist).
constexpr double kMinimumFocalFactor = 1e-3;

/// max(0, d k / (1 + d k)), 0 near or past the centre of curvature.
double clampedWeight(double distance, double curvature) {
  const double focal = 1.0 + distance * curvature;
  if (!(focal > kMinimumFocalFactor)) return 0.0;
  return std::clamp(distance * curvature / focal, 0.0, 1.0);
}

}  // namespace

const char* targetKindName(TargetKind kind) {
  switch (kind) {
    case TargetKind::Surface:
      return "surface";
    case TargetKind::Curve:
      return "curve";
    case TargetKind::Points:
      return "points";
  }
  return "unknown";
}

const char* errorTermName(ErrorTerm term) {
  switch (term) {
    case ErrorTerm::PDM:
      return "pdm";
    case ErrorTerm::TDM:
      return "tdm";
    case ErrorTerm::SDM:
      return "sdm";
  }
  return "unknown";
}

double Approximant::tangentCurvature() const {
  if (kind == TargetKind::Curve) return -k1 * principalNormal.dot(normal);
  return k1;
}

Eigen::Vector3d Approximant::sdmWeights() const {
  if (kind == TargetKind::Points || (flags & kFlagEndPoint) != 0) return Eigen::Vector3d::Ones();
  if (kind == TargetKind::Curve) {
    return {clampedWeight(distance, tangentCurvature()), 1.0, 1.0};
  }
  return {clampedWeight(distance, k1), clampedWeight(distance, k2), 1.0};
}

Eigen::Vector3d Approximant::weights(ErrorTerm term) const {
  switch (term) {
    case ErrorTerm::PDM:
      return Eigen::Vector3d::Ones();
    case ErrorTerm::TDM:
      if (kind == TargetKind::Points || (flags & kFlagEndPoint) != 0) {
        return Eigen::Vector3d::Ones();
      }
      return kind == TargetKind::Curve ? Eigen::Vector3d(0.0, 1.0, 1.0)
                                       : Eigen::Vector3d(0.0, 0.0, 1.0);
    case ErrorTerm::SDM:
      return sdmWeights();
  }
  return Eigen::Vector3d::Ones();
}

QuadraticForm Approximant::form(ErrorTerm term) const {
  const Eigen::Vector3d w = weights(term);
  const Eigen::Vector3d e2 = bitangent();
  QuadraticForm q;
  q.A = w[0] * tangent * tangent.transpose() + w[1] * e2 * e2.transpose() +
        w[2] * normal * normal.transpose();
  q.b = q.A * footpoint;
  q.c = footpoint.dot(q.b);
  return q;
}

std::vector<Approximant> SquaredDistanceTarget::approximantsAt(
    const std::vector<Eigen::Vector3d>& points) const {
  std::vector<Approximant> result(points.size());
  // The first failing index wins, so the error does not depend on the thread count.
  std::atomic<std::size_t> firstFailure{std::numeric_limits<std::size_t>::max()};
  std::exception_ptr failure;
  std::mutex failureMutex;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        if (i > firstFailure.load()) return;
                        try {
                          result[i] = approximantAt(points[i]);
                        } catch (...) {
                          const std::lock_guard<std::mutex> lock(failureMutex);
                          if (i < firstFailure.load()) {
                            firstFailure = i;
                            failure = std::current_exception();
                          }
                          return;
                        }
                      }
                    });
  if (failure) std::rethrow_exception(failure);
  return result;
}

double SquaredDistanceTarget::squaredDistanceAt(const Eigen::Vector3d& point) const {
  return approximantAt(point).form(ErrorTerm::SDM)(point);
}

}  // namespace d2vdb
