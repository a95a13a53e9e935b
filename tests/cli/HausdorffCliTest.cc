// End-to-end tests of 'd2vdb project' and 'd2vdb hausdorff': the worked examples of Chen et al.
// (2010) through the command line, JSON keys, the SVG drawing, exit codes; meshes, points and
// level sets against each other with the heat map and histogram.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;
using d2vdb::test::readWholeFile;

class HausdorffCliTest : public d2vdb::test::CliFixture {
 protected:
  void SetUp() override {
    d2vdb::test::CliFixture::SetUp();
    write("a.json", curveJson(3, "[0, 0, 0, 0, 1, 1, 1, 1]",
                              "[[193, 226], [227, 230], [297, 134], [421, 135]]"));
    write("b.json", curveJson(3, "[0, 0, 0, 0, 1, 1, 1, 1]",
                              "[[258, 481], [294, 438], [302, 268], [435, 213]]"));
    write("quadratic.json", curveJson(2, "[0, 0, 0, 1, 1, 1]", "[[-1, 0], [0, 2], [1, 0]]"));
  }

  static std::string curveJson(int degree, const std::string& knots, const std::string& points) {
    return R"({"type": "bspline_curve", "version": 1, "dimension": 2, "degree": )" +
           std::to_string(degree) + R"(, "knots": )" + knots + R"(, "control_points": )" + points +
           "}\n";
  }
};

TEST_F(HausdorffCliTest, HelpHasExamples) {
  for (const char* subcommand : {"project", "hausdorff"}) {
    const CliResult help = run(std::string(subcommand) + " --help");
    EXPECT_EQ(help.exitCode, 0) << subcommand << help.err;
    EXPECT_NE(help.out.find("Example: d2vdb " + std::string(subcommand)), std::string::npos)
        << help.out;
  }
}

TEST_F(HausdorffCliTest, ProjectSeedQuadraticAsJson) {
  const CliResult result = run("project " + path("quadratic.json") + " 0 0 --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  EXPECT_NEAR(report.at("distance").get<double>(), std::sqrt(3.0) / 2.0, 1e-15);
  EXPECT_NEAR(std::abs(report.at("parameter").get<double>() - 0.5), std::sqrt(2.0) / 4.0, 1e-15);
  ASSERT_EQ(report.at("point").size(), 2u);  // a 2D curve reports 2D points
  EXPECT_NEAR(report.at("point").at(1).get<double>(), 0.5, 1e-15);
  const nlohmann::json& extrema = report.at("extrema");
  ASSERT_EQ(extrema.size(), 5u);
  EXPECT_EQ(extrema.at(1).at("kind"), "minimum");
  EXPECT_EQ(extrema.at(2).at("kind"), "maximum");
  EXPECT_NEAR(extrema.at(2).at("parameter").get<double>(), 0.5, 1e-15);
  EXPECT_TRUE(extrema.at(0).at("end_point").get<bool>());
  for (const char* key : {"curve", "query"}) EXPECT_TRUE(report.contains(key)) << key;
}

TEST_F(HausdorffCliTest, ProjectAcceptsNegativeCoordinatesAndReportsText) {
  const CliResult result = run("project " + path("quadratic.json") + " -2 -1");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("nearest point (-1, 0) at t = 0"), std::string::npos) << result.out;
}

TEST_F(HausdorffCliTest, HausdorffSeedCubicsWithSvg) {
  const CliResult result = run("hausdorff " + path("a.json") + " " + path("b.json") + " --svg " +
                               path("pair.svg") + " --json --quiet");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  EXPECT_NEAR(report.at("distance").get<double>(), 261.912153140809, 1e-9);
  EXPECT_EQ(report.at("larger_direction"), "b_to_a");
  const nlohmann::json& backward = report.at("b_to_a");
  EXPECT_EQ(backward.at("from_parameter").get<double>(), 0.0);
  EXPECT_NEAR(backward.at("to_parameter").get<double>(), 0.0685, 5e-5);
  EXPECT_EQ(backward.at("case").get<int>(), 2);
  EXPECT_NEAR(report.at("a_to_b").at("distance").get<double>(), 160.990456269458, 1e-9);
  EXPECT_TRUE(report.at("converged").get<bool>());
  EXPECT_LE(report.at("lower_bound").get<double>(), report.at("distance").get<double>());
  EXPECT_GE(report.at("upper_bound").get<double>(), report.at("distance").get<double>());
  for (const char* key : {"a", "b", "one_sided", "relative_tolerance", "seconds", "warnings"}) {
    EXPECT_TRUE(report.contains(key)) << key;
  }
  for (const char* key : {"lower_bound", "upper_bound", "from_point", "to_point", "case_name",
                          "converged", "intervals", "depth"}) {
    EXPECT_TRUE(backward.contains(key)) << key;
  }
  const std::string svg = readWholeFile(scratch_ / "pair.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("<line"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

TEST_F(HausdorffCliTest, OneSidedAndText) {
  const CliResult oneSided =
      run("hausdorff " + path("a.json") + " " + path("b.json") + " --one-sided --json");
  ASSERT_EQ(oneSided.exitCode, 0) << oneSided.err;
  const nlohmann::json report = nlohmann::json::parse(oneSided.out);
  EXPECT_NEAR(report.at("distance").get<double>(), 160.990456269458, 1e-9);
  EXPECT_FALSE(report.contains("b_to_a"));
  EXPECT_TRUE(report.at("one_sided").get<bool>());

  const CliResult text = run("hausdorff " + path("a.json") + " " + path("b.json"));
  ASSERT_EQ(text.exitCode, 0) << text.err;
  EXPECT_NE(text.out.find("Hausdorff distance H(A, B) = 261.912153140809"), std::string::npos)
      << text.out;
}

TEST_F(HausdorffCliTest, DepthBoundWarnsAndStillReportsTheBracket) {
  write("wavy.json", curveJson(3, "[0, 0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1, 1]",
                               "[[0, 0], [1, 2], [2, -1], [3, 2.5], [4, -0.5], [5, 1.5], [6, 0]]"));
  write("other.json", curveJson(2, "[0, 0, 0, 0.3, 0.6, 1, 1, 1]",
                                "[[-0.5, 1], [1, 0.5], [2.5, 2], [4, 0], [6.5, 0.8]]"));
  const CliResult result =
      run("hausdorff " + path("wavy.json") + " " + path("other.json") + " --max-depth 1 --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  EXPECT_FALSE(report.at("converged").get<bool>());
  EXPECT_FALSE(report.at("warnings").empty());
  EXPECT_NE(result.err.find("warning:"), std::string::npos);
  EXPECT_LT(report.at("lower_bound").get<double>(), report.at("upper_bound").get<double>());
}

TEST_F(HausdorffCliTest, BadInputsExitWithTwoAndUsageErrorsWithOne) {
  EXPECT_EQ(run("hausdorff " + path("a.json") + " " + path("missing.json")).exitCode, 2);
  write("broken.json", "{\"type\": \"bspline_curve\"");
  EXPECT_EQ(run("hausdorff " + path("a.json") + " " + path("broken.json")).exitCode, 2);
  EXPECT_EQ(run("project " + path("missing.json") + " 0 0").exitCode, 2);
  EXPECT_EQ(run("project " + path("quadratic.json") + " nan 0").exitCode, 2);
  EXPECT_EQ(run("project " + path("quadratic.json") + " 0").exitCode, 1);
  EXPECT_EQ(run("hausdorff " + path("a.json")).exitCode, 1);
  EXPECT_EQ(run("hausdorff " + path("a.json") + " " + path("b.json") + " --tolerance -1").exitCode,
            1);
  // A failed run leaves no SVG behind.
  EXPECT_EQ(run("hausdorff " + path("a.json") + " " + path("missing.json") + " --svg " +
                path("never.svg"))
                .exitCode,
            2);
  EXPECT_FALSE(fs::exists(scratch_ / "never.svg"));
}

// Two boxes worked by hand: A = [0,1]^3, B = [0,2] x [0,1]^2: h(A -> B) = 1/2 (A's face x = 1 lies
// inside B, its centre 1/2 from B's sides), h(B -> A) = 1 (B's face x = 2).
std::string boxObj(double length) {
  std::string obj;
  for (int corner = 0; corner < 8; ++corner) {
    obj += "v " + std::to_string(corner & 1 ? length : 0.0) + " " +
           std::to_string(corner & 2 ? 1.0 : 0.0) + " " + std::to_string(corner & 4 ? 1.0 : 0.0) +
           "\n";
  }
  obj +=
      "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\nf 3 7 4\nf 4 7 8\nf 1 5 3\n"
      "f 3 5 7\nf 2 4 6\nf 4 8 6\n";
  return obj;
}

TEST_F(HausdorffCliTest, MeshesByHandWithHeatmapAndHistogram) {
  write("a.obj", boxObj(1.0));
  write("b.obj", boxObj(2.0));
  const CliResult result =
      run("hausdorff " + path("a.obj") + " " + path("b.obj") + " --tolerance 1e-9 --heatmap " +
          path("heat.ply") + " --histogram " + path("hist.svg") + " --json --quiet");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report.at("method"), "branch and bound");
  EXPECT_LE(report.at("lower_bound").get<double>(), 1.0);
  EXPECT_GE(report.at("upper_bound").get<double>(), 1.0);
  EXPECT_LE(report.at("upper_bound").get<double>() - report.at("lower_bound").get<double>(), 1e-9);
  EXPECT_EQ(report.at("larger_direction"), "b_to_a");
  const nlohmann::json& forward = report.at("a_to_b");
  EXPECT_LE(forward.at("lower_bound").get<double>(), 0.5);
  EXPECT_GE(forward.at("upper_bound").get<double>(), 0.5);
  EXPECT_NEAR(forward.at("from_point").at(0).get<double>(), 1.0, 1e-6);
  for (const char* key : {"tolerance", "diagonal", "shape_a", "shape_b", "b_to_a", "seconds",
                          "converged", "heatmap", "histogram"}) {
    EXPECT_TRUE(report.contains(key)) << key;
  }
  for (const char* key : {"primitives_refined", "depth", "to_point", "distance"}) {
    EXPECT_TRUE(forward.contains(key)) << key;
  }
  EXPECT_EQ(report.at("shape_a").at("kind"), "mesh");
  const std::string ply = readWholeFile(scratch_ / "heat.ply");
  EXPECT_NE(ply.find("property float distance"), std::string::npos);
  EXPECT_NE(ply.find("property uchar red"), std::string::npos);
  EXPECT_NE(ply.find("element vertex 8"), std::string::npos);
  const std::string svg = readWholeFile(scratch_ / "hist.svg");
  EXPECT_NE(svg.find("<rect"), std::string::npos);
  EXPECT_NE(svg.find("vertices"), std::string::npos);
}

TEST_F(HausdorffCliTest, PointsAgainstALevelSetAndTextReport) {
  // The bundled bunny against its level set's marching-cubes mesh: a text answer.
  const std::string volumes = std::string(D2VDB_SOURCE_DIR) + "/volumes/";
  write("points.xyz", "0 0 0\n");
  const CliResult result = run("hausdorff " + volumes + "bunny.obj " + volumes + "bunny.vdb");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("Hausdorff distance H(A, B) in ["), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("marching-cubes mesh"), std::string::npos) << result.out;
  write("a.obj", boxObj(1.0));
  const CliResult inside =
      run("hausdorff " + path("points.xyz") + " " + path("a.obj") + " --one-sided --json");
  ASSERT_EQ(inside.exitCode, 0) << inside.err;
  const nlohmann::json report = nlohmann::json::parse(inside.out);
  EXPECT_EQ(report.at("lower_bound").get<double>(), 0.0);  // the origin is a box corner
  EXPECT_LE(report.at("upper_bound").get<double>(), 1e-6 * std::sqrt(3.0));
  EXPECT_FALSE(report.contains("b_to_a"));
}

TEST_F(HausdorffCliTest, ShapeMisuseExitsWithTwoAndWritesNothing) {
  write("a.obj", boxObj(1.0));
  write("empty.xyz", "");
  EXPECT_EQ(run("hausdorff " + path("a.obj") + " " + path("empty.xyz")).exitCode, 2);
  write("nan.xyz", "0 nan 0\n");
  EXPECT_EQ(
      run("hausdorff " + path("a.obj") + " " + path("nan.xyz") + " --heatmap " + path("never.ply"))
          .exitCode,
      2);
  EXPECT_FALSE(fs::exists(scratch_ / "never.ply"));
  EXPECT_EQ(
      run("hausdorff " + path("a.obj") + " " + path("a.obj") + " --svg " + path("x.svg")).exitCode,
      2);
  EXPECT_EQ(
      run("hausdorff " + path("a.json") + " " + path("b.json") + " --heatmap " + path("x.ply"))
          .exitCode,
      2);
  EXPECT_EQ(run("hausdorff " + path("a.obj") + " " + path("a.obj") + " --tolerance 0").exitCode, 1);
  EXPECT_EQ(run("hausdorff " + path("a.obj") + " " + path("a.obj") + " --heatmap " + path("x.obj"))
                .exitCode,
            2);  // the heat map is a PLY
  EXPECT_FALSE(fs::exists(scratch_ / "x.ply"));
  EXPECT_FALSE(fs::exists(scratch_ / "x.svg"));
}

TEST_F(HausdorffCliTest, ASplineSurfaceAgainstAMeshBothWays) {
  // The biquadratic bump z = 2 (2u(1-u)) (2v(1-v)) over the unit square against the square
  // (two triangles): h(bump -> square) = 1/2 at the top. The other way the square's middle is
  // farthest from the bump, which rises over it.
  write("bump.json",
        R"({"type": "bspline_surface", "version": 1, "degree_u": 2, "degree_v": 2,
            "knots_u": [0, 0, 0, 1, 1, 1], "knots_v": [0, 0, 0, 1, 1, 1],
            "control_points": [[[0, 0, 0], [0, 0.5, 0], [0, 1, 0]],
                               [[0.5, 0, 0], [0.5, 0.5, 2], [0.5, 1, 0]],
                               [[1, 0, 0], [1, 0.5, 0], [1, 1, 0]]]})");
  write("square.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4\nf 1 4 3\n");
  const CliResult oneSided =
      run("hausdorff " + path("bump.json") + " " + path("square.obj") +
          " --one-sided --tolerance 1e-9 --heatmap " + path("bump.ply") + " --json --quiet");
  ASSERT_EQ(oneSided.exitCode, 0) << oneSided.err;
  const nlohmann::json report = nlohmann::json::parse(oneSided.out);
  EXPECT_LE(report.at("lower_bound").get<double>(), 0.5);
  EXPECT_GE(report.at("upper_bound").get<double>(), 0.5);
  EXPECT_LE(report.at("upper_bound").get<double>() - report.at("lower_bound").get<double>(), 1e-9);
  EXPECT_EQ(report.at("shape_a").at("kind"), "surface");
  EXPECT_EQ(report.at("shape_a").at("approximation_error").get<double>(), 0.0);  // exact nets
  EXPECT_NE(readWholeFile(scratch_ / "bump.ply").find("element vertex 10201"), std::string::npos);

  const CliResult both = run("hausdorff " + path("bump.json") + " " + path("square.obj") +
                             " --tolerance 1e-3 --json --quiet");
  ASSERT_EQ(both.exitCode, 0) << both.err;
  const nlohmann::json twoSided = nlohmann::json::parse(both.out);
  const nlohmann::json& back = twoSided.at("b_to_a");
  EXPECT_LE(back.at("upper_bound").get<double>() - back.at("lower_bound").get<double>(), 1e-3);
  EXPECT_NEAR(back.at("from_point").at(0).get<double>(), 0.5, 0.05);
  EXPECT_NEAR(back.at("from_point").at(1).get<double>(), 0.5, 0.05);
  EXPECT_GE(twoSided.at("upper_bound").get<double>(), 0.5);
  EXPECT_LE(twoSided.at("lower_bound").get<double>(), 0.5);
  EXPECT_GT(twoSided.at("shape_a").at("approximation_error").get<double>(), 0.0);
}

}  // namespace
