// Line charts with a logarithmic y axis, such as the convergence of a fit (a distance per
// iteration), drawn on an SvgCanvas.
#pragma once

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

#include "d2vdb/plot/SvgCanvas.h"

namespace d2vdb {

/// One line of a LogPlot: (x, y) points in order; points with y <= 0 or non-finite coordinates
/// are left out (they have no place on a log axis).
struct PlotSeries {
  std::string label;  ///< shown in the legend, in the series' colour
  std::vector<Eigen::Vector2d> points;
};

/// What a LogPlot shows besides its series.
struct LogPlotLabels {
  std::string description;  ///< an XML comment saying what the chart is
  std::string xAxis;        ///< e.g. "iteration (0..12)"
  std::string yAxis;        ///< e.g. "RMS distance"
};

/// A 640 x 420 chart: x linear from 0 to the largest x (at least 1), y logarithmic over whole
/// decades covering every positive y (one decade when there is none), a grid line and a "1eN"
/// label per decade, the axis labels, and one coloured polyline per series with its legend entry
/// (colours repeat after four series).
SvgCanvas logPlot(const std::vector<PlotSeries>& series, const LogPlotLabels& labels);

}  // namespace d2vdb
