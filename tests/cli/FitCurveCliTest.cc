// End-to-end tests of 'd2vdb fit-curve': an ellipse polyline, a point cloud, an offset, the
// history, JSON report, SVG drawings, written curve and exit codes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"
#include "d2vdb/io/SplineJson.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;
using d2vdb::test::readWholeFile;

constexpr double kTwoPi = 6.283185307179586476925;

class FitCurveCliTest : public d2vdb::test::CliFixture {
 protected:
  void SetUp() override {
    d2vdb::test::CliFixture::SetUp();
    // Ellipse a = 1, b = 0.6 as a closed 2D polyline, and as a point cloud.
    std::ostringstream polyline;
    polyline.precision(17);
    polyline << R"({"type": "polyline", "version": 1, "dimension": 2, "closed": true, "points": [)";
    std::ostringstream cloud;
    cloud.precision(17);
    for (int i = 0; i < 2000; ++i) {
      const double t = kTwoPi * i / 2000;
      polyline << (i ? ", " : "") << '[' << std::cos(t) << ", " << 0.6 * std::sin(t) << ']';
      cloud << std::cos(t) << ' ' << 0.6 * std::sin(t) << " 0\n";
    }
    polyline << "]}\n";
    write("ellipse.json", polyline.str());
    write("ellipse.xyz", cloud.str());
  }

  // Largest |(x/a)^2 + (y/b)^2 - 1| scaled to a distance (first order) over the fitted curve.
  static double ellipseError(const d2vdb::BSplineCurve& curve) {
    double worst = 0.0;
    for (const Eigen::Vector3d& p : curve.sample(500)) {
      const double radius = std::hypot(p.x(), p.y() / 0.6);
      worst = std::max(worst, std::abs(radius - 1.0));
    }
    return worst;
  }
};

TEST_F(FitCurveCliTest, HelpHasAnExample) {
  const CliResult help = run("fit-curve --help");
  EXPECT_EQ(help.exitCode, 0) << help.err;
  EXPECT_NE(help.out.find("Example: d2vdb fit-curve"), std::string::npos) << help.out;
}

TEST_F(FitCurveCliTest, FitsAnEllipsePolylineWithPicturesAndComparison) {
  const CliResult result =
      run("fit-curve --target " + path("ellipse.json") + " --init circle --method sdm --ctrl 12 " +
          "--out " + path("fitted.json") + " --svg " + path("fit.svg") + " --plot " +
          path("conv.svg") + " --compare --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["method"], "sdm");
  EXPECT_EQ(report["status"], "converged");
  EXPECT_EQ(report["target_kind"], "polyline");
  EXPECT_LT(report["max_distance"].get<double>(), 2e-3);
  EXPECT_EQ(report["history"].size(), report["iterations"].get<std::size_t>() + 1);
  ASSERT_TRUE(report.contains("compare"));
  EXPECT_GT(report["compare"]["pdm"]["iterations"].get<int>(), report["iterations"].get<int>());
  const d2vdb::BSplineCurve fitted = d2vdb::readCurveJson(scratch_ / "fitted.json");
  EXPECT_TRUE(fitted.isClosed());
  EXPECT_EQ(fitted.controlPointCount(), 12);
  EXPECT_EQ(fitted.dimension(), 2);
  EXPECT_LT(ellipseError(fitted), 2e-3);
  const std::string svg = readWholeFile(scratch_ / "fit.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_GE(static_cast<int>(std::count(svg.begin(), svg.end(), '\n')), 5);
  const std::string plot = readWholeFile(scratch_ / "conv.svg");
  EXPECT_NE(plot.find("sdm ("), std::string::npos);
  EXPECT_NE(plot.find("pdm ("), std::string::npos);
}

TEST_F(FitCurveCliTest, CertifyBracketsTheLargestErrorToThePolyline) {
  // The sampled largest distance is measured to the polyline as well, so it is a lower bound of
  // h(fit -> polyline): the certified upper bound is at least it.
  const CliResult result =
      run("fit-curve --target " + path("ellipse.json") + " --init circle --ctrl 12 --out " +
          path("fitted.json") + " --certify 1e-7 --json -q");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  const nlohmann::json& certified = report.at("certified");
  EXPECT_GE(certified.at("upper_bound").get<double>(), report.at("max_distance").get<double>());
  EXPECT_LE(certified.at("upper_bound").get<double>() - certified.at("lower_bound").get<double>(),
            certified.at("tolerance").get<double>());
  EXPECT_EQ(certified.at("target_as"), "polylines");
}

TEST_F(FitCurveCliTest, PrintsTheHistoryAndFitsAPointCloud) {
  const CliResult result = run("fit-curve --target " + path("ellipse.xyz") +
                               " --init ellipse --ctrl 10 --out " + path("cloud.json"));
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("sdm fit: converged"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("objective"), std::string::npos);
  EXPECT_LT(ellipseError(d2vdb::readCurveJson(scratch_ / "cloud.json")), 2e-3);
}

TEST_F(FitCurveCliTest, FootpointCorrectionCanBeLeftOutForComparison) {
  // Clean samples of the open wave (t, 0.3 sin(1.25 pi t)): with and without the footpoint
  // correction SDM II reaches the same curve; without it, it needs more iterations.
  std::ostringstream cloud;
  cloud.precision(17);
  for (int i = 0; i < 2000; ++i) {
    const double t = -1.0 + 2.0 * (i + 0.5) / 2000;
    cloud << t << ' ' << 0.3 * std::sin(1.25 * kTwoPi / 2.0 * t) << " 0\n";
  }
  write("wave.xyz", cloud.str());
  const std::string command = "fit-curve --target " + path("wave.xyz") +
                              " --init polyline --ctrl 12 --json --out " + path("wave.json");
  const CliResult corrected = run(command);
  const CliResult uncorrected = run(command + " --no-footpoint-correction");
  ASSERT_EQ(corrected.exitCode, 0) << corrected.err;
  ASSERT_EQ(uncorrected.exitCode, 0) << uncorrected.err;
  const nlohmann::json with = nlohmann::json::parse(corrected.out);
  const nlohmann::json without = nlohmann::json::parse(uncorrected.out);
  EXPECT_EQ(with["status"], "converged");
  EXPECT_EQ(without["status"], "converged");
  EXPECT_LT(with["iterations"].get<int>(), without["iterations"].get<int>());
  EXPECT_NEAR(with["rms_distance"].get<double>(), without["rms_distance"].get<double>(),
              0.01 * without["rms_distance"].get<double>());
}

TEST_F(FitCurveCliTest, OffsetFit) {
  const CliResult result = run("fit-curve --target " + path("ellipse.json") +
                               " --offset 0.2 --ctrl 20 --json --out " + path("offset.json"));
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  EXPECT_LT(report["max_distance"].get<double>(), 2e-3);
  // The offset of the ellipse lies outside it: every fitted point is ~0.2 from the ellipse, so
  // well outside (x/1.2)^2 + (y/0.8)^2 < 0.97.
  for (const Eigen::Vector3d& p : d2vdb::readCurveJson(scratch_ / "offset.json").sample(200)) {
    EXPECT_GT(std::hypot(p.x() / 1.2, p.y() / 0.8), 0.97);
  }
}

TEST_F(FitCurveCliTest, BadInputAndUsageErrors) {
  write("empty.xyz", "");
  CliResult result = run("fit-curve --target " + path("empty.xyz") + " --out " + path("o.json"));
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("error:"), std::string::npos);
  EXPECT_FALSE(fs::exists(scratch_ / "o.json"));

  write("bad_knots.json", R"({"type": "bspline_curve", "version": 1, "dimension": 2, "degree": 3, )"
                          R"("knots": [0, 0, 0, 0, 0.8, 0.5, 1, 1, 1, 1], )"
                          R"("control_points": [[0, 0], [1, 2], [2, 2], [3, 0], [4, 1], [5, 0]]})");
  result = run("fit-curve --target " + path("ellipse.json") + " --init " + path("bad_knots.json") +
               " --out " + path("o.json"));
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("knot"), std::string::npos) << result.err;

  result = run("fit-curve --target " + path("ellipse.json") + " --method newton --out " +
               path("o.json"));
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("pdm, tdm, sdm, tdm+pdm"), std::string::npos) << result.err;

  result =
      run("fit-curve --target " + path("ellipse.xyz") + " --offset 0.1 --out " + path("o.json"));
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("--offset needs a curve target"), std::string::npos) << result.err;

  result = run("fit-curve --out " + path("o.json"));  // no --target
  EXPECT_EQ(result.exitCode, 1);
  EXPECT_FALSE(fs::exists(scratch_ / "o.json"));
}

TEST_F(FitCurveCliTest, RefusesWhatTheDataCannotDetermineAndOddTypes) {
  // Five points cannot determine a thousand control points (this used to take gigabytes).
  write("five.xyz", "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 1.5 0\n");
  CliResult result =
      run("fit-curve --target " + path("five.xyz") + " --ctrl 1000 --out " + path("o.json"));
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("--ctrl 1000"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("--ctrl 5 or fewer"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(scratch_ / "o.json"));
  // A polyline target: 100 control points per vertex at most (here 2000 vertices: the limit is
  // not reached by reasonable requests, and a million is refused at once).
  result =
      run("fit-curve --target " + path("ellipse.json") + " --ctrl 1000000 --out " + path("o.json"));
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("--ctrl 200000 or fewer"), std::string::npos) << result.err;

  // A "type" that is not a string is bad input (exit 2) naming the field, not a JSON library
  // exception (exit 3).
  write("odd_type.json",
        R"({"type": 1.5, "version": 1, "dimension": 2, "points": [[0, 0], [1, 1]]})");
  result = run("fit-curve --target " + path("odd_type.json") + " --out " + path("o.json"));
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("\"type\" is 1.5"), std::string::npos) << result.err;

  // Validators name the value, not the range of a double.
  result =
      run("fit-curve --target " + path("ellipse.json") + " --tolerance -1 --out " + path("o.json"));
  EXPECT_EQ(result.exitCode, 1) << result.err;
  EXPECT_NE(result.err.find("must be a number >= 0, got -1"), std::string::npos) << result.err;
  EXPECT_EQ(result.err.find("1.79"), std::string::npos) << result.err;
}

}  // namespace
