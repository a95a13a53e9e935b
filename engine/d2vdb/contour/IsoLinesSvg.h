// Writing slice iso-lines as an SVG drawing.
#pragma once

#include <filesystem>

#include "d2vdb/contour/IsoLines.h"

namespace d2vdb {

/// Writes the lines of `slice` to `path` as an SVG document (SvgCanvas::forView()), atomically:
/// one <polyline> per open line and one <polygon> per closed line, the plane's (u, v) coordinates
/// in world units with v pointing up, a view around all points with a 5% margin, hairline strokes.
/// An empty slice gives an empty drawing. Throws RuntimeFailure when the file cannot be written.
void writeIsoLinesSvg(const std::filesystem::path& path, const Slice& slice);

}  // namespace d2vdb
