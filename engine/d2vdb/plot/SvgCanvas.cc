#include "d2vdb/plot/SvgCanvas.h"

#include <algorithm>
#include <ostream>

#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb {
namespace {

constexpr int kDigits = 9;

// `text` with the five XML special characters escaped.
std::string escaped(const std::string& text) {
  std::string result;
  for (const char c : text) {
    switch (c) {
      case '&':
        result += "&amp;";
        break;
      case '<':
        result += "&lt;";
        break;
      case '>':
        result += "&gt;";
        break;
      case '"':
        result += "&quot;";
        break;
      case '\'':
        result += "&apos;";
        break;
      default:
        result += c;
    }
  }
  return result;
}

}  // namespace

SvgCanvas::SvgCanvas(double width, double height, double pixelWidth, bool flipY,
                     Eigen::Vector2d origin)
    : width_(width), height_(height), pixelWidth_(pixelWidth), flipY_(flipY), origin_(origin) {}

SvgCanvas SvgCanvas::forView(const Eigen::AlignedBox2d& view, double margin, double pixelWidth) {
  Eigen::AlignedBox2d box = view.isEmpty() ? Eigen::AlignedBox2d(Eigen::Vector2d::Zero()) : view;
  // A flat side gets a tenth of the other side (or 1 when both are flat).
  const double larger = box.sizes().maxCoeff();
  const double minimum = larger > 0.0 ? 0.1 * larger : 1.0;
  for (int axis = 0; axis < 2; ++axis) {
    const double missing = minimum - box.sizes()[axis];
    if (missing > 0.0) {
      box.min()[axis] -= 0.5 * missing;
      box.max()[axis] += 0.5 * missing;
    }
  }
  const double pad = std::max(0.0, margin) * box.sizes().maxCoeff();
  const Eigen::Vector2d size = box.sizes() + Eigen::Vector2d::Constant(2.0 * pad);
  return SvgCanvas(size.x(), size.y(), pixelWidth, true,
                   Eigen::Vector2d(box.min().x() - pad, box.max().y() + pad));
}

SvgCanvas SvgCanvas::forPoints(const std::vector<Eigen::Vector3d>& points, double margin,
                               double pixelWidth) {
  Eigen::AlignedBox2d view;
  for (const Eigen::Vector3d& point : points) view.extend(point.head<2>().eval());
  return forView(view, margin, pixelWidth);
}

SvgCanvas SvgCanvas::page(double width, double height) {
  return SvgCanvas(width, height, width, false, Eigen::Vector2d::Zero());
}

Eigen::Vector2d SvgCanvas::map(const Eigen::Vector2d& point) const {
  return flipY_ ? Eigen::Vector2d(point.x() - origin_.x(), origin_.y() - point.y())
                : Eigen::Vector2d(point - origin_);
}

std::string SvgCanvas::number(double value) const {
  return formatNumber(value, kDigits);
}

std::string SvgCanvas::styleAttributes(const SvgStyle& style) const {
  std::string attributes = "fill=\"" + escaped(style.fill) + "\" stroke=\"" +
                           escaped(style.stroke) + "\" stroke-width=\"" +
                           number(style.strokeWidth) + "\"";
  if (!style.dashes.empty()) attributes += " stroke-dasharray=\"" + escaped(style.dashes) + "\"";
  if (style.hairline) attributes += " vector-effect=\"non-scaling-stroke\"";
  return attributes;
}

std::string SvgCanvas::pointList(const std::vector<Eigen::Vector2d>& points) const {
  std::string list;
  for (const Eigen::Vector2d& point : points) {
    const Eigen::Vector2d p = map(point);
    list += (list.empty() ? "" : " ") + number(p.x()) + "," + number(p.y());
  }
  return list;
}

void SvgCanvas::title(const std::string& text) {
  body_ += "  <title>" + escaped(text) + "</title>\n";
}

void SvgCanvas::comment(const std::string& text) {
  std::string safe = text;  // "--" may not appear inside an XML comment
  for (std::size_t at = safe.find("--"); at != std::string::npos; at = safe.find("--", at)) {
    safe.replace(at, 2, "- -");
  }
  body_ += "  <!-- " + safe + " -->\n";
}

void SvgCanvas::polyline(const std::vector<Eigen::Vector2d>& points, const SvgStyle& style,
                         bool closed) {
  if (points.empty()) return;
  body_ += std::string("  <") + (closed ? "polygon " : "polyline ") + styleAttributes(style) +
           " points=\"" + pointList(points) + "\"/>\n";
}

void SvgCanvas::polyline(const std::vector<Eigen::Vector3d>& points, const SvgStyle& style,
                         bool closed) {
  std::vector<Eigen::Vector2d> planar;
  planar.reserve(points.size());
  for (const Eigen::Vector3d& point : points) planar.push_back(point.head<2>());
  polyline(planar, style, closed);
}

void SvgCanvas::line(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                     const SvgStyle& style) {
  const Eigen::Vector2d a = map(from), b = map(to);
  body_ += "  <line x1=\"" + number(a.x()) + "\" y1=\"" + number(a.y()) + "\" x2=\"" +
           number(b.x()) + "\" y2=\"" + number(b.y()) + "\" " + styleAttributes(style) + "/>\n";
}

void SvgCanvas::circle(const Eigen::Vector2d& center, double radius, const SvgStyle& style) {
  const Eigen::Vector2d c = map(center);
  body_ += "  <circle cx=\"" + number(c.x()) + "\" cy=\"" + number(c.y()) + "\" r=\"" +
           number(radius) + "\" " + styleAttributes(style) + "/>\n";
}

void SvgCanvas::rectangle(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                          const SvgStyle& style) {
  const Eigen::Vector2d p = map(a), q = map(b);
  const Eigen::Vector2d low = p.cwiseMin(q), size = (p - q).cwiseAbs();
  body_ += "  <rect x=\"" + number(low.x()) + "\" y=\"" + number(low.y()) + "\" width=\"" +
           number(size.x()) + "\" height=\"" + number(size.y()) + "\" " + styleAttributes(style) +
           "/>\n";
}

void SvgCanvas::text(const Eigen::Vector2d& position, const std::string& text,
                     const SvgTextStyle& style) {
  const Eigen::Vector2d p = map(position);
  static constexpr const char* kAnchors[] = {"start", "middle", "end"};
  body_ += "  <text x=\"" + number(p.x()) + "\" y=\"" + number(p.y()) + "\" font-size=\"" +
           number(style.size) + "\" fill=\"" + escaped(style.color) + "\" text-anchor=\"" +
           kAnchors[static_cast<int>(style.anchor)] + "\"";
  if (style.rotation != 0.0) {
    body_ += " transform=\"rotate(" + number(style.rotation) + " " + number(p.x()) + " " +
             number(p.y()) + ")\"";
  }
  body_ += ">" + escaped(text) + "</text>\n";
}

std::string SvgCanvas::document() const {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " +
         number(width_) + " " + number(height_) + "\" width=\"" + number(pixelWidth_) +
         "\" height=\"" + number(pixelWidth_ * height_ / width_) +
         "\" font-family=\"sans-serif\">\n" + body_ + "</svg>\n";
}

void SvgCanvas::write(const std::filesystem::path& path) const {
  const std::string text = document();
  writeStreamAtomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace d2vdb
