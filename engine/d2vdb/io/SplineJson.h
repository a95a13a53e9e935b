// Reading and writing B-spline curves and surfaces as JSON files (format below).
#pragma once

#include <filesystem>
#include <string>
#include <variant>

#include "d2vdb/spline/BSplineCurve.h"
#include "d2vdb/spline/BSplineSurface.h"

// d2vdb spline JSON format, version 1
// ===================================
// One JSON object per file. Every field listed is required unless marked optional; other fields
// are rejected (so a misspelt optional field is an error, not silently ignored). Numbers are JSON
// numbers (integers or decimals; NaN, infinity and null are rejected); d2vdb writes every double
// in its shortest round-trip form, so write-then-read reproduces each value bit for bit.
//
// Curve:
//   {
//     "type": "bspline_curve",
//     "version": 1,
//     "dimension": 2,               2 or 3: number of coordinates per control point
//     "degree": 3,                  integer 1..15
//     "closed": false,              optional, default false
//     "knots": [0, 0, 0, 0, 0.5, 1, 1, 1, 1],
//     "control_points": [[0, 0], [1, 2], [2, 2], [3, 0], [4, 1]]
//   }
//   Open curve: len(knots) = len(control_points) + degree + 1, knots non-decreasing and finite,
//   a knot value strictly inside the domain [knots[degree], knots[len(control_points)]] repeated
//   at most degree times, values at or beyond the domain ends at most degree + 1 times, and a
//   non-empty domain. Clamped and unclamped knot vectors are both accepted.
//   Closed curve ("closed": true): control_points holds the n unique points only; knots holds
//   the full uniform periodic knot vector of n + 2 degree + 1 equally spaced values (the curve's
//   domain is [knots[degree], knots[n + degree]]), as an ordinary B-spline evaluator needs it
//   together with the wrapped points P_0..P_{n-1}, P_0..P_{degree-1}. Readers check that the
//   spacing is uniform to within 1e-9 of the domain length and that n >= degree + 1.
//   2D curves store [x, y]; d2vdb represents them with z = 0.
//
// Surface:
//   {
//     "type": "bspline_surface",
//     "version": 1,
//     "degree_u": 3,                integer 1..15
//     "degree_v": 2,                integer 1..15
//     "closed_u": false,            optional, default false
//     "closed_v": false,            optional, default false
//     "knots_u": [...],
//     "knots_v": [...],
//     "control_points": [[[x, y, z], ...], ...]
//   }
//   control_points[i][j] = P_ij: the outer array runs over u (count_u rows), each row over v
//   (count_v points of three coordinates); S(u, v) = sum_ij N_i(u) M_j(v) P_ij. Each direction
//   follows the curve rules: open, count = len(knots) - degree - 1; closed, the rows (or
//   columns) are the unique ones and the knots are uniform periodic with count + 2 degree + 1
//   values.
//
// Errors: every malformed input throws InputError naming the file (or "<string>") and the JSON
// path of the offending field, e.g. "spline file 'a.json', field 'control_points[3][1]': expected
// a number, got null"; invalid JSON reports nlohmann's byte offset.

namespace d2vdb {

/// A curve or a surface, as read by readSplineJson().
using Spline = std::variant<BSplineCurve, BSplineSurface>;

/// Reads a "bspline_curve" file. Throws InputError when the file is missing or unreadable, is not
/// valid JSON, or violates the format (message names the file and field).
BSplineCurve readCurveJson(const std::filesystem::path& file);

/// Reads a "bspline_surface" file. Failure behaviour as readCurveJson().
BSplineSurface readSurfaceJson(const std::filesystem::path& file);

/// Reads a curve or surface file, chosen by its "type" field. Failure behaviour as readCurveJson().
Spline readSplineJson(const std::filesystem::path& file);

/// Parses curve JSON text; `sourceName` stands for the file name in error messages.
BSplineCurve parseCurveJson(const std::string& text, const std::string& sourceName = "<string>");

/// Parses surface JSON text; `sourceName` stands for the file name in error messages.
BSplineSurface parseSurfaceJson(const std::string& text,
                                const std::string& sourceName = "<string>");

/// Parses curve or surface JSON text, chosen by its "type" field.
Spline parseSplineJson(const std::string& text, const std::string& sourceName = "<string>");

/// The curve as JSON text in the format above (full precision, one control point per line).
std::string curveToJson(const BSplineCurve& curve);

/// The surface as JSON text in the format above (full precision, one control point row per line).
std::string surfaceToJson(const BSplineSurface& surface);

/// Writes curveToJson(curve) to `file` atomically (writeStreamAtomically). Throws
/// RuntimeFailure when the file cannot be written; an existing file is then left unchanged.
void writeCurveJson(const std::filesystem::path& file, const BSplineCurve& curve);

/// Writes surfaceToJson(surface) to `file` atomically. Failure behaviour as writeCurveJson().
void writeSurfaceJson(const std::filesystem::path& file, const BSplineSurface& surface);

}  // namespace d2vdb
