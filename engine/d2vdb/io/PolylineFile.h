// Reading and writing polylines as JSON files (format below), and reading the polylines of
// `d2vdb slice --polylines` files.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "d2vdb/field/CurveTarget.h"

// d2vdb polyline JSON format, version 1
// =====================================
// One JSON object per file; every field is required unless marked optional, other fields are
// rejected. Numbers must be finite JSON numbers; d2vdb writes them in shortest round-trip form.
//   {
//     "type": "polyline",
//     "version": 1,
//     "dimension": 2,            2 or 3: coordinates per point
//     "closed": false,           optional, default false; a closed polyline joins the last point
//                                to the first, which is not repeated
//     "points": [[0, 0], [1, 0.5], [2, 0]]
//   }
//   At least 2 points (3 when closed). 2D polylines store [x, y]; d2vdb represents them with z = 0.
//
// Slice files (`d2vdb slice --polylines`) are read as well:
//   {"axis": "z", "offset": 0.1, "iso": 0, "plane_axes": ["x", "y"],
//    "polylines": [{"closed": true, "points": [[u, v], ...]}, ...]}
//   Each entry becomes a 2D polyline in the plane coordinates (u, v) along plane_axes, z = 0.
//
// Errors: InputError naming the file (or "<string>") and the JSON path of the offending field,
// e.g. "polyline file 'a.json', field 'points[3][1]': expected a number, got null".

namespace d2vdb {

/// Every polyline of a polyline file (one) or a slice file (any number, possibly none). Throws
/// InputError for a missing or unreadable file, invalid JSON, or a violation of the format.
std::vector<Polyline> readPolylines(const std::filesystem::path& file);

/// The one polyline of a polyline file, or of a slice file holding exactly one. Failure behaviour
/// as readPolylines(); also throws InputError saying how many polylines the file holds when that
/// is not one.
Polyline readPolyline(const std::filesystem::path& file);

/// The one polyline of `polylines` (read from `file`, which names it in the message). Throws
/// InputError saying how many polylines the file holds when that is not one.
Polyline onlyPolyline(std::vector<Polyline> polylines, const std::filesystem::path& file);

/// Parses polyline or slice JSON text; `sourceName` stands for the file name in messages.
std::vector<Polyline> parsePolylines(const std::string& text,
                                     const std::string& sourceName = "<string>");

/// The polyline as JSON text in the format above (one point per line). Throws InputError for a
/// dimension other than 2 or 3, fewer than 2 points (3 when closed), a non-finite coordinate or
/// a 2D polyline with z != 0.
std::string polylineToJson(const Polyline& polyline);

/// Writes polylineToJson(polyline) to `file` atomically. Throws InputError as polylineToJson()
/// (before writing) and RuntimeFailure when the file cannot be written (an existing file is then
/// left unchanged).
void writePolyline(const std::filesystem::path& file, const Polyline& polyline);

}  // namespace d2vdb
