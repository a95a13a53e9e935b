#include "d2vdb/plot/Histogram.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "d2vdb/core/NumberFormat.h"

namespace d2vdb {

std::vector<std::size_t> histogramCounts(const std::vector<double>& values, int bins,
                                         double* largest) {
  std::vector<std::size_t> counts(static_cast<std::size_t>(std::max(bins, 1)), 0);
  double top = 0.0;
  for (const double value : values) top = std::max(top, value);
  for (const double value : values) {
    const double position = top > 0.0 ? value / top * static_cast<double>(counts.size()) : 0.0;
    const auto bin = static_cast<std::size_t>(std::clamp(position, 0.0, counts.size() - 1.0));
    ++counts[bin];
  }
  if (largest != nullptr) *largest = top;
  return counts;
}

SvgCanvas histogramPlot(const std::vector<double>& values, int bins,
                        const HistogramLabels& labels) {
  double largest = 0.0;
  const std::vector<std::size_t> counts = histogramCounts(values, bins, &largest);
  const std::size_t highest =
      std::max<std::size_t>(1, *std::max_element(counts.begin(), counts.end()));

  constexpr double kWidth = 640.0, kHeight = 420.0;
  constexpr double kLeft = 70.0, kRight = 20.0, kTop = 36.0, kBottom = 50.0;
  const double plotWidth = kWidth - kLeft - kRight, plotHeight = kHeight - kTop - kBottom;
  const auto xAt = [&](double value) {
    return kLeft + plotWidth * (largest > 0.0 ? value / largest : 0.0);
  };
  const auto yAt = [&](double count) {
    return kTop + plotHeight * (1.0 - count / double(highest));
  };

  SvgCanvas canvas = SvgCanvas::page(kWidth, kHeight);
  if (!labels.description.empty()) canvas.comment(labels.description);
  if (!labels.title.empty()) {
    canvas.title(labels.title);
    SvgTextStyle heading;
    heading.anchor = TextAnchor::Middle;
    heading.size = 14.0;
    canvas.text({kWidth / 2.0, 22.0}, labels.title, heading);
  }
  const double barWidth = plotWidth / static_cast<double>(counts.size());
  for (std::size_t bin = 0; bin < counts.size(); ++bin) {
    if (counts[bin] == 0) continue;
    const double left = kLeft + barWidth * static_cast<double>(bin);
    canvas.rectangle({left, yAt(double(counts[bin]))}, {left + barWidth, yAt(0.0)},
                     SvgStyle::filled("#1f4e9c"));
  }
  canvas.rectangle({kLeft, kTop}, {kWidth - kRight, kHeight - kBottom}, SvgStyle{});

  SvgTextStyle tick;
  tick.anchor = TextAnchor::Middle;
  for (int step = 0; step <= 4; ++step) {
    const double value = largest * step / 4.0;
    canvas.text({xAt(value), kHeight - kBottom + 16.0}, formatNumber(value, 4), tick);
  }
  tick.anchor = TextAnchor::End;
  canvas.text({kLeft - 6.0, kTop + 4.0}, std::to_string(highest), tick);
  canvas.text({kLeft - 6.0, kHeight - kBottom + 4.0}, "0", tick);
  if (!values.empty()) {
    std::vector<double> sorted = values;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2];
    canvas.line(Eigen::Vector2d(xAt(median), kTop), Eigen::Vector2d(xAt(median), yAt(0.0)),
                SvgStyle::stroked("#b3261e", 1.5, "5 3"));
    SvgTextStyle note;
    note.color = "#b3261e";
    canvas.text({xAt(median) + 4.0, kTop + 14.0}, "median " + formatNumber(median, 4), note);
  }
  SvgTextStyle axis;
  axis.anchor = TextAnchor::Middle;
  canvas.text({kLeft + plotWidth / 2.0, kHeight - 12.0}, labels.xAxis, axis);
  axis.rotation = -90.0;
  canvas.text({16.0, kTop + plotHeight / 2.0}, labels.yAxis, axis);
  return canvas;
}

}  // namespace d2vdb
