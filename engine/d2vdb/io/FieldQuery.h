// Answering an approximant field at query points, one or many: the one call behind every answer of
// `d2vdb query` (a single point, a point file, a field file read in part).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/field/ApproximantField.h"

namespace d2vdb {

/// Whether the field answered a query point.
enum class QueryStatus : std::uint8_t {
  Ok = 0,             ///< answered (approximant and level are set)
  OutsideDomain = 1,  ///< the point lies outside the field's working domain: no answer
};

/// Name of a status: "ok", "outside_domain" (the status values of query result files).
const char* queryStatusName(QueryStatus status);

/// The field's answer at one point.
struct FieldAnswer {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< the query point (world)
  QueryStatus status = QueryStatus::Ok;
  int level = -1;             ///< the level that answered (0 = the band), -1 without an answer
  Approximant approximant{};  ///< ApproximantField::approximantAt(point); default without answer
};

/// The answer of `field` at `point` through `accessor` (which must belong to `field`): a point
/// outside the working domain gets QueryStatus::OutsideDomain instead of an error, every other
/// point ApproximantField::Accessor::approximantAt() and the level that answered. Throws
/// InputError for a non-finite point.
FieldAnswer answerAt(const ApproximantField& field, ApproximantField::Accessor& accessor,
                     const Eigen::Vector3d& point);

/// answerAt() for every point, in order, in parallel (TBB; each answer depends on its point only,
/// so the result is bitwise the same for any thread count). Throws InputError naming the first
/// non-finite point before any work.
std::vector<FieldAnswer> answerAll(const ApproximantField& field,
                                   const std::vector<Eigen::Vector3d>& points);

/// The message of a query outside the working domain `domain`: the point, how far outside it lies
/// and the domain, worded as what ApproximantField::approximantAt() throws there.
std::string outsideDomainMessage(const Eigen::AlignedBox3d& domain, const Eigen::Vector3d& point);

/// Throws InputError naming the (0-based) index of the first non-finite point of `points`.
void requireFinitePoints(const std::vector<Eigen::Vector3d>& points, const std::string& source);

}  // namespace d2vdb
