// A histogram chart: how a list of values (distances, errors) is distributed.
#pragma once

#include <string>
#include <vector>

#include "d2vdb/plot/SvgCanvas.h"

namespace d2vdb {

/// What a histogram shows and says.
struct HistogramLabels {
  std::string title;        ///< above the chart (may be empty)
  std::string xAxis;        ///< e.g. "distance to B (world units)"
  std::string yAxis;        ///< e.g. "vertices"
  std::string description;  ///< an XML comment for a reader of the file (may be empty)
};

/// The number of values in each of `bins` equal bins over [0, largest] (largest = the largest
/// value; a value equal to it falls in the last bin). Values must be finite and >= 0; bins >= 1.
/// All values 0 give every count in the first bin.
std::vector<std::size_t> histogramCounts(const std::vector<double>& values, int bins,
                                         double* largest);

/// A bar chart of histogramCounts(values, bins) with the bins' range on the x axis, the counts on
/// the y axis, and the median and largest value marked. Values must be finite and >= 0; no values
/// give an empty chart with its axes.
SvgCanvas histogramPlot(const std::vector<double>& values, int bins, const HistogramLabels& labels);

}  // namespace d2vdb
