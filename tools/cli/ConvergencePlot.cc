// The convergence plot of the fitting commands (ConvergencePlot.h), drawn by plot/LogPlot.h.
#include "ConvergencePlot.h"

#include <algorithm>

#include "d2vdb/plot/LogPlot.h"

namespace d2vdb::cli {

void writeConvergencePlot(const std::string& file, const std::vector<ConvergenceSeries>& runs,
                          const std::string& command) {
  std::vector<PlotSeries> series;
  int maxIteration = 1;
  for (const ConvergenceSeries& run : runs) {
    PlotSeries line;
    line.label = std::string(fitMethodName(run.method)) + " (" + std::to_string(run.iterations) +
                 " iterations, " + fitStatusName(run.status) + ")";
    for (const FitIteration& row : *run.history) {
      line.points.emplace_back(row.iteration, row.rmsDistance);
    }
    series.push_back(std::move(line));
    maxIteration = std::max(maxIteration, run.iterations);
  }
  LogPlotLabels labels;
  labels.description = "d2vdb " + command + ": RMS distance per iteration, log scale";
  labels.xAxis = "iteration (0.." + std::to_string(maxIteration) + ")";
  labels.yAxis = "RMS distance";
  logPlot(series, labels).write(file);
}

}  // namespace d2vdb::cli
