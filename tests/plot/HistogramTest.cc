// Histogram counts against hand counts, and the chart's parts.
#include <gtest/gtest.h>

#include "d2vdb/plot/Histogram.h"

namespace d2vdb {
namespace {

TEST(Histogram, CountsFallInEqualBinsUpToTheLargestValue) {
  double largest = 0.0;
  const std::vector<std::size_t> counts =
      histogramCounts({0.0, 0.1, 0.24, 0.26, 0.5, 0.74, 1.0, 1.0}, 4, &largest);
  EXPECT_EQ(largest, 1.0);
  EXPECT_EQ(counts, (std::vector<std::size_t>{3, 1, 2, 2}));  // 1.0 counts in the last bin
  const std::vector<std::size_t> zeros = histogramCounts({0.0, 0.0}, 3, &largest);
  EXPECT_EQ(zeros, (std::vector<std::size_t>{2, 0, 0}));
  EXPECT_EQ(largest, 0.0);
}

TEST(Histogram, ChartHasBarsAxesAndMedian) {
  HistogramLabels labels;
  labels.title = "distances";
  labels.xAxis = "distance";
  labels.yAxis = "vertices";
  const std::string svg = histogramPlot({1.0, 2.0, 2.0, 3.0, 10.0}, 10, labels).document();
  EXPECT_NE(svg.find("<rect"), std::string::npos);
  EXPECT_NE(svg.find("median 2"), std::string::npos) << svg;
  EXPECT_NE(svg.find(">vertices<"), std::string::npos);
  EXPECT_NE(svg.find(">10<"), std::string::npos);  // the largest value on the x axis
  const std::string empty = histogramPlot({}, 10, labels).document();
  EXPECT_NE(empty.find("</svg>"), std::string::npos);
}

}  // namespace
}  // namespace d2vdb
