// End-to-end tests of 'd2vdb fit-surface': the bundled torus level set (JSON report keys, surface
// file, PLY mesh with distances and colours, plot), a ruled surface with its rulings on an exact
// B-spline target, 'info' on the result, and bad input (exit 2, nothing written).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"
#include "d2vdb/fit/InitialSurface.h"
#include "d2vdb/io/SplineJson.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;
using d2vdb::test::readWholeFile;

class FitSurfaceCliTest : public d2vdb::test::CliFixture {};

TEST_F(FitSurfaceCliTest, TorusLevelSetGivesSurfaceMeshPlotAndReport) {
  const std::string torus = std::string(D2VDB_SOURCE_DIR) + "/volumes/torus.vdb";
  const CliResult result =
      run("fit-surface --target '" + torus + "' --init torus --ctrl 8,6 --iterations 20 --out " +
          path("torus.json") + " --mesh " + path("torus.ply") + " --plot " + path("conv.svg") +
          " --json -q");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  for (const char* key :
       {"method", "status", "reason", "iterations", "rms_distance", "max_distance", "history",
        "target", "target_kind", "offset", "dimension", "degree", "control_points", "closed",
        "output", "plot", "seconds", "mesh"}) {
    EXPECT_TRUE(report.contains(key)) << key;
  }
  EXPECT_EQ(report["target_kind"], "field");
  EXPECT_EQ(report["closed"], nlohmann::json({true, true}));
  EXPECT_EQ(report["history"].size(), report["iterations"].get<std::size_t>() + 1);
  // The bundled torus has radii 1 and 0.35 at voxel 0.025 (volumes/README.md): an 8 x 6 net
  // gets within a few thousandths of it.
  EXPECT_LT(report["rms_distance"].get<double>(), 3e-3);
  const d2vdb::BSplineSurface surface = d2vdb::readSurfaceJson(scratch_ / "torus.json");
  EXPECT_EQ(surface.countU(), 8);
  EXPECT_TRUE(surface.isClosedU() && surface.isClosedV());
  const std::string ply = readWholeFile(scratch_ / "torus.ply");
  EXPECT_NE(ply.find("property float distance\nproperty uchar red"), std::string::npos);
  EXPECT_NE(readWholeFile(scratch_ / "conv.svg").find("fit-surface"), std::string::npos);
  const CliResult info = run("info --json " + path("torus.json"));
  ASSERT_EQ(info.exitCode, 0) << info.err;
  EXPECT_EQ(nlohmann::json::parse(info.out)["kind"], "bspline_surface");
}

TEST_F(FitSurfaceCliTest, TorusFromWrongRadiiRestartsUnlessTold) {
  // The bundled torus (radii 1 and 0.35) from a torus of radii 0.7 and 0.6: the first steps crowd
  // the parameters, so the fit re-parametrises by chord length and restarts, which --no-restart
  // leaves out.
  const std::string torus = std::string(D2VDB_SOURCE_DIR) + "/volumes/torus.vdb";
  d2vdb::writeSurfaceJson(
      scratch_ / "wrong.json",
      d2vdb::torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.7, 0.6,
                          d2vdb::SurfaceLayout{3, 3, 8, 6, true, true}));
  const std::string command = "fit-surface --target '" + torus + "' --init " + path("wrong.json") +
                              " --iterations 12 --out " + path("fit.json") + " --json -q";
  const CliResult restarted = run(command);
  ASSERT_EQ(restarted.exitCode, 0) << restarted.err;
  EXPECT_NE(nlohmann::json::parse(restarted.out)["reason"].get<std::string>().find("chord length"),
            std::string::npos)
      << restarted.out;
  const CliResult once = run(command + " --no-restart");
  ASSERT_EQ(once.exitCode, 0) << once.err;
  EXPECT_EQ(nlohmann::json::parse(once.out)["reason"].get<std::string>().find("chord length"),
            std::string::npos)
      << once.out;
}

TEST_F(FitSurfaceCliTest, RuledSurfaceOnAnExactTargetWritesItsRulings) {
  // z = xy over [0, 1]^2 as a bilinear B-spline surface. Default (automatic) smoothing: without
  // it the sheet slides over the one-sided target and may stop on a near-exact sub-sheet.
  std::ofstream(scratch_ / "hp.json")
      << R"({"type": "bspline_surface", "version": 1, "degree_u": 1, "degree_v": 1,
            "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
            "control_points": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]})";
  const CliResult result =
      run("fit-surface --target " + path("hp.json") +
          " --init plane --ruled --degree 1,3 --ctrl 2,4 --out " + path("fit.json") +
          " --rulings " + path("rulings.json") + " --json -q");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["degree"], nlohmann::json({1, 3}));
  EXPECT_TRUE(report["ruled"].get<bool>());
  const nlohmann::json rulings = nlohmann::json::parse(readWholeFile(scratch_ / "rulings.json"));
  EXPECT_EQ(rulings["type"], "rulings");
  ASSERT_GT(rulings["rulings"].size(), 4u);
  // Every ruling is a straight segment whose points lie on z = xy to the fit's accuracy.
  for (const nlohmann::json& ruling : rulings["rulings"]) {
    EXPECT_LT(ruling["max_distance"].get<double>(), 1e-5);
    for (const char* end : {"start", "end"}) {
      const double x = ruling[end][0], y = ruling[end][1], z = ruling[end][2];
      EXPECT_NEAR(z, x * y, 1e-5);
    }
  }
}

TEST_F(FitSurfaceCliTest, BadInputExitsWithTwoAndWritesNothing) {
  const std::string torus = "'" + std::string(D2VDB_SOURCE_DIR) + "/volumes/torus.vdb'";
  std::ofstream(scratch_ / "few.xyz") << "0 0 0\n1 0 0\n0 1 0\n";
  std::ofstream(scratch_ / "nan.xyz") << "0 0 nan\n";
  for (const std::string& arguments :
       {"--target " + path("missing.vdb"), "--target " + path("nan.xyz"),
        "--target " + path("few.xyz"), "--target " + torus + " --init torus --ctrl 3,8",
        "--target " + torus + " --init plane --degree 3,3 --ctrl 8,3",
        "--target " + torus + " --init plane --rulings " + path("r.json")}) {
    const CliResult result = run("fit-surface " + arguments + " --out " + path("out.json") + " -q");
    EXPECT_EQ(result.exitCode, 2) << arguments << ": " << result.err;
    EXPECT_FALSE(result.err.empty());
    EXPECT_FALSE(fs::exists(scratch_ / "out.json")) << arguments;
    EXPECT_FALSE(fs::exists(scratch_ / "r.json")) << arguments;
  }
}

}  // namespace

TEST_F(FitSurfaceCliTest, CertifyBracketsTheLargestErrorAboveTheSampledOne) {
  // A bicubic sheet fitted to the hyperbolic paraboloid z = xy (an exact B-spline target): the
  // sampled largest error is a lower bound of h(fit -> target), so the certified upper bound is
  // at least it.
  std::ofstream(scratch_ / "hp.json")
      << R"({"type": "bspline_surface", "version": 1, "degree_u": 1, "degree_v": 1,
            "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
            "control_points": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]})";
  const CliResult result =
      run("fit-surface --target " + path("hp.json") + " --init plane --ctrl 4,4 --out " +
          path("fit.json") + " --certify 1e-3 --json -q");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  const nlohmann::json& certified = report.at("certified");
  EXPECT_GE(certified.at("upper_bound").get<double>(), report.at("max_distance").get<double>());
  EXPECT_LE(certified.at("lower_bound").get<double>(), certified.at("upper_bound").get<double>());
  EXPECT_LE(certified.at("upper_bound").get<double>() - certified.at("lower_bound").get<double>(),
            certified.at("tolerance").get<double>());
  EXPECT_TRUE(certified.at("converged").get<bool>());
  // An offset fit is not compared, and says so before fitting.
  const CliResult offset =
      run("fit-surface --target " + path("hp.json") +
          " --init plane --ctrl 4,4 --offset 0.1 --out " + path("never.json") + " --certify 1e-4");
  EXPECT_EQ(offset.exitCode, 2);
  EXPECT_NE(offset.err.find("--certify"), std::string::npos) << offset.err;
  EXPECT_FALSE(std::filesystem::exists(scratch_ / "never.json"));
}
