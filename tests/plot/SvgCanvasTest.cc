// SvgCanvas and logPlot: coordinates land where the mapping says (checked by hand), text is
// escaped, degenerate views still give a drawing, and the chart has one grid line per decade.
#include "d2vdb/plot/SvgCanvas.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "common/ScratchDirectory.h"
#include "d2vdb/plot/LogPlot.h"

namespace d2vdb {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t found = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
    ++found;
  }
  return found;
}

TEST(SvgCanvas, ViewCanvasPadsTheViewAndPointsYUp) {
  // View [1, 5] x [2, 4], margin 0.25 of the larger side (4): padded to [0, 6] x [1, 5].
  const SvgCanvas canvas = SvgCanvas::forView(
      Eigen::AlignedBox2d(Eigen::Vector2d(1, 2), Eigen::Vector2d(5, 4)), 0.25, 600);
  EXPECT_DOUBLE_EQ(canvas.extent(), 6.0);
  // The padded top-left corner (0, 5) is the canvas origin; y grows downward on the canvas.
  EXPECT_TRUE(canvas.map(Eigen::Vector2d(0, 5)).isApprox(Eigen::Vector2d(0, 0)));
  EXPECT_TRUE(canvas.map(Eigen::Vector2d(1, 2)).isApprox(Eigen::Vector2d(1, 3)));
  EXPECT_TRUE(canvas.map(Eigen::Vector3d(6, 1, 7)).isApprox(Eigen::Vector2d(6, 4)));
  const std::string svg = canvas.document();
  EXPECT_NE(svg.find("viewBox=\"0 0 6 4\""), std::string::npos) << svg;
  EXPECT_NE(svg.find("width=\"600\" height=\"400\""), std::string::npos) << svg;
}

TEST(SvgCanvas, DegenerateViewsStillHaveASize) {
  // A horizontal segment: the flat side gets a tenth of the other.
  const SvgCanvas flat =
      SvgCanvas::forView(Eigen::AlignedBox2d(Eigen::Vector2d(0, 3), Eigen::Vector2d(10, 3)), 0.0);
  EXPECT_TRUE(flat.map(Eigen::Vector2d(0, 3)).isApprox(Eigen::Vector2d(0, 0.5)));
  EXPECT_NE(flat.document().find("viewBox=\"0 0 10 1\""), std::string::npos);
  // Nothing at all: a unit square around the origin.
  const SvgCanvas empty = SvgCanvas::forPoints({}, 0.0);
  EXPECT_DOUBLE_EQ(empty.extent(), 1.0);
  EXPECT_TRUE(empty.map(Eigen::Vector2d(0, 0)).isApprox(Eigen::Vector2d(0.5, 0.5)));
}

TEST(SvgCanvas, ElementsAreWrittenWithTheirStyleAndEscapedText) {
  SvgCanvas canvas = SvgCanvas::page(100, 50);
  canvas.title("a < b & c");
  canvas.comment("no -- inside");
  SvgStyle dashed;
  dashed.stroke = "#1f4e9c";
  dashed.strokeWidth = 0.5;
  dashed.dashes = "6 4";
  canvas.polyline(std::vector<Eigen::Vector2d>{{0, 0}, {10, 20}, {30, 5}}, dashed);
  SvgStyle hairline;
  hairline.hairline = true;
  canvas.polyline(std::vector<Eigen::Vector2d>{{1, 1}, {2, 1}, {2, 2}}, hairline, true);
  canvas.polyline(std::vector<Eigen::Vector2d>{}, hairline);  // nothing to draw
  canvas.circle(Eigen::Vector2d(5, 6), 1.5, SvgStyle{});
  canvas.rectangle(Eigen::Vector2d(9, 8), Eigen::Vector2d(3, 4), SvgStyle{});
  SvgTextStyle label;
  label.anchor = TextAnchor::End;
  label.rotation = -90;
  canvas.text(Eigen::Vector2d(7, 8), "\"quoted\"", label);
  const std::string svg = canvas.document();
  EXPECT_NE(svg.find("<title>a &lt; b &amp; c</title>"), std::string::npos) << svg;
  EXPECT_NE(svg.find("<!-- no - - inside -->"), std::string::npos) << svg;
  EXPECT_NE(svg.find("stroke=\"#1f4e9c\" stroke-width=\"0.5\" stroke-dasharray=\"6 4\" "
                     "points=\"0,0 10,20 30,5\""),
            std::string::npos)
      << svg;
  EXPECT_NE(svg.find("<polygon fill=\"none\" stroke=\"black\" stroke-width=\"1\" "
                     "vector-effect=\"non-scaling-stroke\" points=\"1,1 2,1 2,2\""),
            std::string::npos)
      << svg;
  EXPECT_EQ(count(svg, "<polyline"), 1u);
  EXPECT_NE(svg.find("<circle cx=\"5\" cy=\"6\" r=\"1.5\""), std::string::npos) << svg;
  EXPECT_NE(svg.find("<rect x=\"3\" y=\"4\" width=\"6\" height=\"4\""), std::string::npos) << svg;
  EXPECT_NE(svg.find("text-anchor=\"end\" transform=\"rotate(-90 7 8)\">&quot;quoted&quot;</text>"),
            std::string::npos)
      << svg;
}

class SvgCanvasFile : public test::ScratchDirectoryTest {};

TEST_F(SvgCanvasFile, WritesTheDocument) {
  SvgCanvas canvas = SvgCanvas::page(10, 10);
  canvas.circle(Eigen::Vector2d(1, 1), 1, SvgStyle{});
  canvas.write(file("c.svg"));
  EXPECT_EQ(test::readWholeFile(file("c.svg")), canvas.document());
}

TEST(LogPlot, OneGridLinePerDecadeAndOneLinePerSeries) {
  // RMS 1e-1 down to 3e-5: decades 1e-5 .. 1e-1 (five grid lines); x from 0 to 4.
  PlotSeries sdm{"sdm (4 iterations, converged)", {{0, 1e-1}, {1, 1e-2}, {2, 1e-3}, {4, 3e-5}}};
  PlotSeries pdm{"pdm", {{0, 1e-1}, {1, 0.0}, {2, 5e-2}}};  // the zero has no place on the axis
  LogPlotLabels labels;
  labels.description = "test chart";
  labels.xAxis = "iteration (0..4)";
  labels.yAxis = "RMS distance";
  const std::string svg = logPlot({sdm, pdm}, labels).document();
  EXPECT_EQ(count(svg, "stroke=\"#dddddd\""), 5u) << svg;
  EXPECT_EQ(svg.find(">1e0<"), std::string::npos);
  for (const char* decade : {">1e-5<", ">1e-4<", ">1e-3<", ">1e-2<", ">1e-1<"}) {
    EXPECT_NE(svg.find(decade), std::string::npos) << decade;
  }
  EXPECT_EQ(count(svg, "<polyline"), 2u);
  EXPECT_NE(svg.find(">sdm (4 iterations, converged)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">iteration (0..4)</text>"), std::string::npos);
  // The plot area spans x 70..620 and y 20..370 for 1e-1..1e-5: the point (4, 3e-5) lies at
  // x = 620 and y = 20 + 350 (-1 - log10(3e-5)) / 4.
  const double y = 20.0 + 350.0 * (-1.0 - std::log10(3e-5)) / 4.0;
  char expected[64];
  std::snprintf(expected, sizeof(expected), " 620,%.9g\"", y);
  EXPECT_NE(svg.find(expected), std::string::npos) << expected << "\n" << svg;
  // The pdm series skips its zero: (0, 0.1) at the top, then (2, 0.05).
  EXPECT_NE(svg.find("points=\"70,20 345,"), std::string::npos) << svg;
}

}  // namespace
}  // namespace d2vdb
