// Internal to the io module: d2vdb's JSON documents (SplineJson.h, PolylineFile.h,
// SupportFunctionJson.h) from a document that is already parsed, so that a reader that looked at
// its "type" first need not parse it again.
#pragma once

#include <string>
#include <vector>

#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/io/SupportFunctionJson.h"
#include "d2vdb/io/detail/JsonReader.h"
#include "d2vdb/spline/BSplineCurve.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb::detail {

/// The curve of a parsed "bspline_curve" document; `sourceName` names the file in messages.
/// Failure behaviour as parseCurveJson().
BSplineCurve curveFromJson(const Json& document, const std::string& sourceName);

/// The surface of a parsed "bspline_surface" document. Failure behaviour as parseSurfaceJson().
BSplineSurface surfaceFromJson(const Json& document, const std::string& sourceName);

/// The polylines of a parsed polyline or slice document. Failure behaviour as parsePolylines().
std::vector<Polyline> polylinesFromJson(const Json& document, const std::string& sourceName);

/// The support function of a parsed "support_function" document. Failure behaviour as
/// parseSupportFunctionJson().
SupportFunctionDocument supportFunctionFromJson(const Json& document,
                                                const std::string& sourceName);

}  // namespace d2vdb::detail
