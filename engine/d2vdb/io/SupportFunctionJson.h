// Reading and writing support functions (support/SupportFunction.h) as JSON files (format below).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "d2vdb/support/SphericalTriangulation.h"
#include "d2vdb/support/SupportFunction.h"

// d2vdb support-function JSON format, version 1
// =============================================
// One JSON object per file. Every field listed is required unless marked optional; other fields
// are rejected at every level (a misspelt optional field is an error, not silently ignored).
// Numbers are JSON numbers (NaN, infinity and null are rejected); d2vdb writes every double in its
// shortest round-trip form, so write-then-read reproduces each value bit for bit.
//
//   {
//     "type": "support_function",
//     "version": 1,
//     "basis": "real_spherical_harmonics",   the orthonormal real harmonics of
//                                            support/SphericalHarmonics.h (no Condon-Shortley
//                                            phase; coefficient of Y_l^m at index l^2 + l + m)
//     "degree": 16,                          integer 0..64
//     "coefficients": [c_0, c_1, ...],       (degree + 1)^2 numbers, world units:
//                                            h(n) = sum_j c_j Y_j(n)
//     "domain": {"kind": "sphere"},          the whole sphere of normals (a closed surface), or
//               {"kind": "patch",            a patch: the Gauss image the function was fitted
//                "normals": [[x, y, z], ...],  over, as a triangulation of the sphere (unit
//                "triangles": [[i, j, k], ...]}  normals to within 1e-9; triangles index them,
//                                            counter-clockwise seen from outside the sphere)
//     "fit": {                               optional: how the coefficients were obtained
//       "source": "bunny.obj",               input file (or a description)
//       "samples": 34817,                    oriented samples fitted
//       "regularization": 1e-10,             lambda of SupportFit.h
//       "rms_residual": 1.2e-4,              sqrt(mean |X_i - x_h(n_i)|^2), world units
//       "max_residual": 9.1e-4               max |X_i - x_h(n_i)|
//     }
//   }
//
// Errors: every malformed input throws InputError naming the file (or "<string>") and the JSON
// path of the offending field, e.g. "support-function file 'a.json', field 'coefficients[3]':
// expected a number, got null"; invalid JSON reports nlohmann's byte offset.

namespace d2vdb {

/// The optional "fit" record of a support-function file.
struct SupportFitRecord {
  std::string source;
  std::uint64_t samples = 0;
  double regularization = 0.0;
  double rmsResidual = 0.0;
  double maxResidual = 0.0;
};

/// The content of a support-function file.
struct SupportFunctionDocument {
  SupportFunction function;
  /// The patch domain; empty for the whole sphere.
  std::optional<SphericalTriangulation> patch;
  std::optional<SupportFitRecord> fit;
};

/// The "type" value of support-function files: "support_function".
inline constexpr const char* kSupportFunctionJsonType = "support_function";

/// Reads a support-function file. Throws InputError when the file is missing or unreadable, is not
/// valid JSON, or violates the format (message names the file and field).
SupportFunctionDocument readSupportFunctionJson(const std::filesystem::path& file);

/// Parses support-function JSON text; `sourceName` stands for the file name in error messages.
SupportFunctionDocument parseSupportFunctionJson(const std::string& text,
                                                 const std::string& sourceName = "<string>");

/// The document as JSON text in the format above (full precision). Throws InputError for a fit
/// record with a non-finite number or a patch that is not a valid triangulation.
std::string supportFunctionToJson(const SupportFunctionDocument& document);

/// Writes supportFunctionToJson(document) to `file` atomically. Throws InputError as
/// supportFunctionToJson (before writing) and RuntimeFailure when the file cannot be written (an
/// existing file is then left unchanged).
void writeSupportFunctionJson(const std::filesystem::path& file,
                              const SupportFunctionDocument& document);

}  // namespace d2vdb
