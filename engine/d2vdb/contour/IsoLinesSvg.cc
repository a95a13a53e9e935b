// SVG output of slice iso-lines (IsoLinesSvg.h).
#include "d2vdb/contour/IsoLinesSvg.h"

#include <Eigen/Geometry>

#include <vector>

#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/plot/SvgCanvas.h"

namespace d2vdb {

void writeIsoLinesSvg(const std::filesystem::path& path, const Slice& slice) {
  Eigen::AlignedBox2d box;
  for (const IsoLine& line : slice.lines) {
    for (const auto& point : line.points) box.extend(point);
  }
  if (box.isEmpty()) box = Eigen::AlignedBox2d(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1));
  SvgCanvas canvas = SvgCanvas::forView(box);
  const char* axisNames = "xyz";
  canvas.title(std::string("iso-lines of the plane ") + axisNames[slice.axis] + " = " +
               formatNumber(slice.offset, 9) + " (horizontal " + axisNames[slice.planeAxes[0]] +
               ", vertical " + axisNames[slice.planeAxes[1]] + ")");
  SvgStyle hairline;
  hairline.hairline = true;
  for (const IsoLine& line : slice.lines) {
    canvas.polyline(line.points, hairline, line.closed);
  }
  canvas.write(path);
}

}  // namespace d2vdb
