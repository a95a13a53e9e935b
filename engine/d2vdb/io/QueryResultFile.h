// Files of field answers at many points (`d2vdb query FIELD --points P --out R`): .csv, .json and
// binary .ply, with one documented, stable set of columns.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/io/FieldQuery.h"

// d2vdb query result files
// ========================
// One record per query point, in the order of the point file, with these columns (world units,
// world frame; every quantity `d2vdb query FIELD X Y Z` reports, from the same call, answerAt()):
//   x y z                        the query point
//   status                       "ok" or "outside_domain" (PLY: uchar 0 or 1)
//   level                        the level that answered, 0 = the narrow band (PLY: int)
//   distance                     signed for surfaces (< 0 inside), unsigned for curves and points
//   squared_distance_estimate    the SDM form at the point (the approximant of d^2)
//   origin_{x,y,z}               the voxel centre (band) or the point (beyond) the data belong to
//   footpoint_{x,y,z}            the closest target point
//   normal_{x,y,z}               unit normal (surfaces: outward; curves, points: toward origin)
//   tangent_{x,y,z}              e1, the first principal direction (curves: the unit tangent)
//   bitangent_{x,y,z}            normal x tangent (surfaces: e2, the second principal direction)
//   k1 k2                        principal curvatures along e1, e2 (1 / world units; a sphere of
//                                radius R has 1/R); curves: k1 the curvature, k2 = 0; points: 0
//   principal_normal_{x,y,z}     curves: the unit principal normal (zero where the curvature is
//                                0); surfaces and points: 0
//   flags                        ApproximantFlag bits (Approximant.h): 1 cut locus, 2 curvature
//                                clamped, 4 degraded estimate, 8 far field, 16 end point (PLY:
//                                ushort)
//   sdm_weights_{1,2,3}          the SDM weights along tangent, bitangent, normal
//   sdm_A_{xx,xy,...,zz}         the SDM form Q(x) = x^T A x - 2 b.x + c: A, row by row (9)
//   sdm_b_{x,y,z} sdm_c          ... its b and c
//   with allForms, then pdm_A_..., pdm_b_..., pdm_c, tdm_A_..., tdm_b_..., tdm_c likewise.
// A point outside the field's working domain has status "outside_domain" and no answer: its other
// values are empty (CSV), null (JSON), NaN (PLY; level -1, flags 0).
// Formats, chosen by the extension of the output (any letter case):
//   .csv   a header line with the column names above, then one line per point; numbers with the
//          fewest digits that read back bit for bit (std::to_chars).
//   .json  {"format": "d2vdb query results", "version": 1, "field", "kind", "count", "answered",
//          "outside_domain", "points": [{"index", "point": [x, y, z], "status", "level",
//          "distance", "squared_distance_estimate", "origin": [..], "footpoint": [..], "normal",
//          "tangent", "bitangent", "k1", "k2", "principal_normal", "flags", "sdm_weights": [..],
//          "forms": {"sdm": {"A": [[3] x 3], "b": [..], "c"}, "pdm", "tdm"}}, ...]}, one point
//          per line, numbers as in .csv.
//   .ply   binary little-endian PLY, one vertex per point with the columns above as properties
//          (double unless noted), readable by any PLY reader.
// Output depends only on the field, the points and the options: bitwise the same for any thread
// count.

namespace d2vdb {

/// The format of a query result file.
enum class QueryResultFormat { Csv, Json, Ply };

/// The format named by the extension of `path`: .csv, .json or .ply in any letter case. Throws
/// InputError naming the path and the accepted extensions otherwise.
QueryResultFormat queryResultFormat(const std::filesystem::path& path);

/// What goes into a query result file.
struct QueryResultOptions {
  bool allForms = false;  ///< add the PDM and TDM forms (as `d2vdb query --form all`)
  std::string field;      ///< the field's file name, written to the JSON header
};

/// The flattened column names of a result file with `options`, in order (the list above).
std::vector<std::string> queryResultColumns(const QueryResultOptions& options);

/// What a batch query answered.
struct QueryResultSummary {
  std::uint64_t count = 0;            ///< query points
  std::uint64_t answered = 0;         ///< status ok
  std::uint64_t outsideDomain = 0;    ///< status outside_domain
  std::vector<std::uint64_t> levels;  ///< answered points per level (index = level)
};

/// Answers `field` at every point (answerAt(), in parallel blocks) and writes the results to
/// `path` (format by extension) atomically, without holding all answers in memory. Throws
/// InputError before any work for an unknown extension or a non-finite point (naming its index),
/// RuntimeFailure when the file cannot be written; an existing file at `path` is then unchanged.
QueryResultSummary writeFieldQueries(const std::filesystem::path& path,
                                     const ApproximantField& field,
                                     const std::vector<Eigen::Vector3d>& points,
                                     const QueryResultOptions& options);

/// Writes answers already computed (answerAll()) to `path` like writeFieldQueries(), for a field
/// of `kind`: the same bytes writeFieldQueries() writes for their points.
QueryResultSummary writeQueryAnswers(const std::filesystem::path& path, TargetKind kind,
                                     const std::vector<FieldAnswer>& answers,
                                     const QueryResultOptions& options);

}  // namespace d2vdb
