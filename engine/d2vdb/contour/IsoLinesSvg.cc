// SVG output of slice iso-lines (IsoLinesSvg.h).
#include "d2vdb/contour/IsoLinesSvg.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <iomanip>
#include <ostream>

#include "d2vdb/core/AtomicFile.h"

namespace d2vdb {

void writeIsoLinesSvg(const std::filesystem::path& path, const Slice& slice) {
  Eigen::AlignedBox2d box;
  for (const IsoLine& line : slice.lines) {
    for (const auto& point : line.points) box.extend(point);
  }
  if (box.isEmpty()) box = Eigen::AlignedBox2d(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1));
  const double margin = 0.05 * std::max(box.sizes().maxCoeff(), 1e-9);
  const Eigen::Vector2d low = box.min() - Eigen::Vector2d::Constant(margin);
  const Eigen::Vector2d size = box.sizes() + Eigen::Vector2d::Constant(2 * margin);
  const char* axisNames = "xyz";
  writeStreamAtomically(path, [&](std::ostream& out) {
    out << std::setprecision(9);
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"800\" height=\""
        << std::max(1.0, 800.0 * size.y() / size.x()) << "\" viewBox=\"" << low.x() << ' '
        << -(low.y() + size.y()) << ' ' << size.x() << ' ' << size.y() << "\">\n"
        << "<title>iso-lines of the plane " << axisNames[slice.axis] << " = " << slice.offset
        << " (horizontal " << axisNames[slice.planeAxes[0]] << ", vertical "
        << axisNames[slice.planeAxes[1]] << ")</title>\n"
        << "<g fill=\"none\" stroke=\"black\" stroke-width=\"1\" "
           "vector-effect=\"non-scaling-stroke\" transform=\"scale(1,-1)\">\n";
    for (const IsoLine& line : slice.lines) {
      if (line.points.empty()) continue;
      out << "<path vector-effect=\"non-scaling-stroke\" d=\"M";
      for (std::size_t i = 0; i < line.points.size(); ++i) {
        out << (i == 0 ? " " : " L ") << line.points[i].x() << ' ' << line.points[i].y();
      }
      out << (line.closed ? " Z" : "") << "\"/>\n";
    }
    out << "</g>\n</svg>\n";
  });
}

}  // namespace d2vdb
