#include "d2vdb/plot/LogPlot.h"

#include <array>
#include <cmath>
#include <limits>

namespace d2vdb {

SvgCanvas logPlot(const std::vector<PlotSeries>& series, const LogPlotLabels& labels) {
  const auto plotted = [](const Eigen::Vector2d& point) {
    return point.allFinite() && point.y() > 0.0;
  };
  double low = std::numeric_limits<double>::infinity(), high = 0.0, right = 1.0;
  for (const PlotSeries& line : series) {
    for (const Eigen::Vector2d& point : line.points) {
      if (!plotted(point)) continue;
      low = std::min(low, point.y());
      high = std::max(high, point.y());
      right = std::max(right, point.x());
    }
  }
  if (!(high > 0.0)) low = high = 1.0;
  // Whole decades around the values (a value at a power of ten, up to rounding, bounds its decade).
  const double top = std::ceil(std::log10(high) - 1e-12);
  double bottom = std::floor(std::log10(low) + 1e-12);
  if (bottom >= top) bottom = top - 1.0;

  constexpr double kWidth = 640.0, kHeight = 420.0;
  constexpr double kLeft = 70.0, kRight = 20.0, kTop = 20.0, kBottom = 50.0;
  const auto at = [&](double x, double y) {
    return Eigen::Vector2d(
        kLeft + (kWidth - kLeft - kRight) * x / right,
        kTop + (kHeight - kTop - kBottom) * (top - std::log10(y)) / (top - bottom));
  };
  static constexpr std::array<const char*, 4> kColors = {"#b3261e", "#1f4e9c", "#2e7d32",
                                                         "#6a1b9a"};

  SvgCanvas canvas = SvgCanvas::page(kWidth, kHeight);
  if (!labels.description.empty()) canvas.comment(labels.description);
  canvas.rectangle({kLeft, kTop}, {kWidth - kRight, kHeight - kBottom}, SvgStyle{});
  const SvgStyle grid = SvgStyle::stroked("#dddddd", 1.0);
  SvgTextStyle tick;
  tick.anchor = TextAnchor::End;
  for (double decade = bottom; decade <= top + 1e-9; decade += 1.0) {
    const double y = at(0.0, std::pow(10.0, decade)).y();
    canvas.line(Eigen::Vector2d(kLeft, y), Eigen::Vector2d(kWidth - kRight, y), grid);
    canvas.text({kLeft - 6.0, y + 4.0}, "1e" + std::to_string(static_cast<int>(decade)), tick);
  }
  SvgTextStyle axis;
  axis.anchor = TextAnchor::Middle;
  canvas.text({(kLeft + kWidth - kRight) / 2.0, kHeight - 12.0}, labels.xAxis, axis);
  axis.rotation = -90.0;
  canvas.text({16.0, (kTop + kHeight - kBottom) / 2.0}, labels.yAxis, axis);

  for (std::size_t i = 0; i < series.size(); ++i) {
    const SvgStyle stroke = SvgStyle::stroked(kColors[i % kColors.size()], 2.0);
    std::vector<Eigen::Vector2d> points;
    for (const Eigen::Vector2d& point : series[i].points) {
      if (plotted(point)) points.push_back(at(point.x(), point.y()));
    }
    canvas.polyline(points, stroke);
    SvgTextStyle legend;
    legend.anchor = TextAnchor::End;
    legend.color = stroke.stroke;
    canvas.text({kWidth - kRight - 10.0, kTop + 20.0 + 16.0 * static_cast<double>(i)},
                series[i].label, legend);
  }
  return canvas;
}

}  // namespace d2vdb
