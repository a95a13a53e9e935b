// Writing slice iso-lines as an SVG drawing.
#pragma once

#include <filesystem>

#include "d2vdb/contour/IsoLines.h"

namespace d2vdb {

/// Writes the lines of `slice` to `path` as an SVG document, atomically: one <path> per line
/// (closed lines end with "Z"), in world units with the v axis pointing up, a view box around all
/// points with a 5% margin, hairline strokes. An empty slice gives an empty drawing. Throws
/// RuntimeFailure when the file cannot be written.
void writeIsoLinesSvg(const std::filesystem::path& path, const Slice& slice);

}  // namespace d2vdb
