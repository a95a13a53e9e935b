// A small SVG canvas: the drawings of slice, fit-curve and hausdorff and the convergence plots are
// made of polylines, lines, circles, rectangles and text on one of these.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace d2vdb {

/// How an element is stroked and filled. Colours are SVG colours ("#1f4e9c", "black", "none").
struct SvgStyle {
  std::string stroke = "black";  ///< outline colour; "none" for no outline
  double strokeWidth = 1.0;      ///< in canvas units (world units on a view canvas)
  std::string fill = "none";     ///< fill colour
  std::string dashes;            ///< stroke-dasharray, e.g. "6 4"; empty for a solid line
  /// Stroke width in screen pixels whatever the zoom (vector-effect="non-scaling-stroke").
  bool hairline = false;

  /// An outline of `color`, `width` wide, dashed by `dashes` when not empty; no fill.
  static SvgStyle stroked(std::string color, double width, std::string dashes = "") {
    SvgStyle style;
    style.stroke = std::move(color);
    style.strokeWidth = width;
    style.dashes = std::move(dashes);
    return style;
  }
  /// A shape filled with `color`, without outline.
  static SvgStyle filled(std::string color) {
    SvgStyle style;
    style.stroke = "none";
    style.fill = std::move(color);
    return style;
  }
};

/// Where text stands relative to its position.
enum class TextAnchor { Start, Middle, End };

/// How text is drawn: font size in canvas units, colour, anchor, and a rotation in degrees
/// (clockwise on screen) about its position.
struct SvgTextStyle {
  double size = 12.0;
  std::string color = "black";
  TextAnchor anchor = TextAnchor::Start;
  double rotation = 0.0;
};

/// An SVG document being drawn, written out in one piece by write() or document().
///
/// Two kinds of canvas: forView() maps world coordinates (x right, y up, only x and y are used)
/// onto a drawing of a given pixel width, keeping proportions; page() uses its own units (x right,
/// y down), for charts. Every coordinate goes through map(), numbers are written with 9
/// significant digits, and text is escaped. Nothing here throws except write().
class SvgCanvas {
 public:
  /// A canvas showing `view` padded on every side by `margin` times its larger side, drawn
  /// `pixelWidth` pixels wide (height in proportion). A view that is empty or flat in x or y is
  /// widened so that the drawing keeps a positive size.
  static SvgCanvas forView(const Eigen::AlignedBox2d& view, double margin = 0.05,
                           double pixelWidth = 800.0);
  /// forView() of the xy projection of `points`.
  static SvgCanvas forPoints(const std::vector<Eigen::Vector3d>& points, double margin = 0.05,
                             double pixelWidth = 800.0);
  /// A canvas `width` x `height` units (and pixels), y pointing down.
  static SvgCanvas page(double width, double height);

  /// Canvas coordinates of a point (world for forView(), units for page()).
  Eigen::Vector2d map(const Eigen::Vector2d& point) const;
  Eigen::Vector2d map(const Eigen::Vector3d& point) const { return map(point.head<2>().eval()); }
  /// The larger side of the drawn area in canvas units: a scale for stroke widths and dot sizes.
  double extent() const { return std::max(width_, height_); }

  /// Adds a <title> (shown by viewers as the drawing's name).
  void title(const std::string& text);
  /// Adds an XML comment (describing the drawing for a reader of the file).
  void comment(const std::string& text);

  /// An open polyline through `points`, or a closed polygon.
  void polyline(const std::vector<Eigen::Vector2d>& points, const SvgStyle& style,
                bool closed = false);
  void polyline(const std::vector<Eigen::Vector3d>& points, const SvgStyle& style,
                bool closed = false);
  void line(const Eigen::Vector2d& from, const Eigen::Vector2d& to, const SvgStyle& style);
  void line(const Eigen::Vector3d& from, const Eigen::Vector3d& to, const SvgStyle& style) {
    line(from.head<2>().eval(), to.head<2>().eval(), style);
  }
  /// A circle of `radius` canvas units around `center`.
  void circle(const Eigen::Vector2d& center, double radius, const SvgStyle& style);
  void circle(const Eigen::Vector3d& center, double radius, const SvgStyle& style) {
    circle(center.head<2>().eval(), radius, style);
  }
  /// The axis-aligned rectangle with opposite corners `a` and `b`.
  void rectangle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const SvgStyle& style);
  void text(const Eigen::Vector2d& position, const std::string& text,
            const SvgTextStyle& style = {});

  /// The whole SVG document.
  std::string document() const;
  /// Writes document() to `path` atomically. Throws RuntimeFailure when the file cannot be
  /// written (an existing file is then left unchanged).
  void write(const std::filesystem::path& path) const;

 private:
  SvgCanvas(double width, double height, double pixelWidth, bool flipY, Eigen::Vector2d origin);
  std::string number(double value) const;
  std::string styleAttributes(const SvgStyle& style) const;
  std::string pointList(const std::vector<Eigen::Vector2d>& points) const;

  double width_, height_, pixelWidth_;
  bool flipY_;
  Eigen::Vector2d origin_;  // world point drawn at the canvas's top-left corner
  std::string body_;
};

}  // namespace d2vdb
