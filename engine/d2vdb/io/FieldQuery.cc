// Answers of an approximant field at query points (FieldQuery.h).
#include "d2vdb/io/FieldQuery.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <cmath>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb {

const char* queryStatusName(QueryStatus status) {
  return status == QueryStatus::Ok ? "ok" : "outside_domain";
}

FieldAnswer answerAt(const ApproximantField& field, ApproximantField::Accessor& accessor,
                     const Eigen::Vector3d& point) {
  if (!point.allFinite()) {
    throw InputError("field query: the point " + formatPoint(point, 6) + " is not finite");
  }
  FieldAnswer answer;
  answer.point = point;
  // The accessor's own test of the domain, so that exactly the points it refuses are reported.
  if (!field.domain().contains(point)) {
    answer.status = QueryStatus::OutsideDomain;
    return answer;
  }
  answer.approximant = accessor.approximantAt(point);
  answer.level = accessor.lastLevel();
  return answer;
}

void requireFinitePoints(const std::vector<Eigen::Vector3d>& points, const std::string& source) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      throw InputError(source + ": query point " + std::to_string(i) + " " +
                       formatPoint(points[i], 6) + " is not finite");
    }
  }
}

std::vector<FieldAnswer> answerAll(const ApproximantField& field,
                                   const std::vector<Eigen::Vector3d>& points) {
  requireFinitePoints(points, "field query");
  std::vector<FieldAnswer> answers(points.size());
  // Answers depend on their point only; the fixed blocks just keep each accessor's leaf cache warm
  // over consecutive (often coherent) points.
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, points.size(), 256),
      [&](const tbb::blocked_range<std::size_t>& range) {
        ApproximantField::Accessor accessor(field);
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          answers[i] = answerAt(field, accessor, points[i]);
        }
      },
      tbb::simple_partitioner());
  return answers;
}

std::string outsideDomainMessage(const Eigen::AlignedBox3d& domain, const Eigen::Vector3d& point) {
  const double outside = std::sqrt(domain.squaredExteriorDistance(point));
  return "the point " + formatPoint(point, 6) + " lies " + formatNumber(outside, 6) +
         " outside the field's working domain " + formatPoint(domain.min(), 6) + " to " +
         formatPoint(domain.max(), 6);
}

}  // namespace d2vdb
