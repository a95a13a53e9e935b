// End-to-end tests of `d2vdb field`, `d2vdb query` and `d2vdb info` on fields: a field from the
// bundled torus level set queried against the analytic torus, curve and point-set fields against
// their exact geometry, and the error paths with their exit codes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/PolylineFile.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;
using d2vdb::test::readWholeFile;
using Eigen::Vector3d;

// volumes/README.md: torus about +z, major radius 1, minor radius 0.35, voxel size 0.025.
constexpr double kMajor = 1.0;
constexpr double kMinor = 0.35;
constexpr double kVoxel = 0.025;

Vector3d jsonVector(const nlohmann::json& value) {
  return {value.at(0).get<double>(), value.at(1).get<double>(), value.at(2).get<double>()};
}

// Exact geometry of the torus at a point off the tube's axis circle.
struct TorusReference {
  double distance;
  Vector3d footpoint;
  Vector3d normal;
  double tubeCurvature;      // along the meridian: 1 / minor radius
  double parallelCurvature;  // along the parallel: cos(theta) / (major + minor cos(theta))
  Vector3d parallelDirection;
};

TorusReference torusAt(const Vector3d& p) {
  const Vector3d radial = Vector3d(p.x(), p.y(), 0.0).normalized();
  const Vector3d center = kMajor * radial;
  const Vector3d normal = (p - center).normalized();
  const double cosTheta = normal.dot(radial);
  return {(p - center).norm() - kMinor,
          center + kMinor * normal,
          normal,
          1.0 / kMinor,
          cosTheta / (kMajor + kMinor * cosTheta),
          Vector3d::UnitZ().cross(radial)};
}

class FieldCliTest : public d2vdb::test::CliFixture {
 protected:
  static std::string torusVdb() {
    return std::string("'") + D2VDB_SOURCE_DIR + "/volumes/torus.vdb'";
  }

  nlohmann::json query(const std::string& field, const Vector3d& point,
                       const std::string& extra = "") const {
    std::ostringstream arguments;
    arguments.precision(17);
    // Options first: after "--" every word is a coordinate (negative numbers included).
    arguments << "query " << field << " --json " << extra << " -- " << point.x() << ' ' << point.y()
              << ' ' << point.z();
    const CliResult result = run(arguments.str());
    EXPECT_EQ(result.exitCode, 0) << result.err;
    return nlohmann::json::parse(result.out);
  }
};

TEST_F(FieldCliTest, TorusFieldAnswersLikeTheAnalyticTorus) {
  const CliResult built = run("field " + torusVdb() + " " + path("torus-field.vdb") + " --json");
  ASSERT_EQ(built.exitCode, 0) << built.err;
  const auto report = nlohmann::json::parse(built.out);
  for (const char* key : {"input", "input_kind", "output", "kind", "estimator", "voxel_size",
                          "half_width", "domain", "levels", "coarse_levels_built", "active_voxels",
                          "memory_bytes", "dense_bytes", "flagged", "seconds", "warnings"}) {
    EXPECT_TRUE(report.contains(key)) << key;
  }
  EXPECT_EQ(report["kind"], "surface");
  EXPECT_EQ(report["input_kind"], "level set");
  EXPECT_NEAR(report["voxel_size"].get<double>(), kVoxel, 1e-9);
  EXPECT_EQ(report["active_voxels"], 132136);  // the level set's band (volumes/README.md)
  // Writing the field needs the band only: the coarse levels wait for a query beyond it.
  EXPECT_EQ(report["levels"].size(), 1u);
  EXPECT_EQ(report["coarse_levels_built"], false);
  EXPECT_LT(report["memory_bytes"].get<double>(), report["dense_bytes"].get<double>());
  ASSERT_TRUE(fs::exists(scratch_ / "torus-field.vdb"));

  // Points in the band on the outer (convex) and inner (saddle) sides and above the tube.
  const std::vector<Vector3d> points = {Vector3d(1.37, 0.02, 0.03), Vector3d(-0.45, 0.39, -0.05),
                                        Vector3d(0.52, 0.55, 0.31)};
  for (const Vector3d& point : points) {
    const nlohmann::json answer = query(path("torus-field.vdb"), point);
    EXPECT_EQ(answer["kind"], "surface");
    EXPECT_EQ(answer["level"], 0) << point.transpose();
    // The data belong to the voxel centre `origin` (within half a voxel diagonal of the point).
    const Vector3d origin = jsonVector(answer["origin"]);
    EXPECT_LE((origin - point).norm(), 0.5 * std::sqrt(3.0) * kVoxel + 1e-9);
    const TorusReference exact = torusAt(origin);
    EXPECT_NEAR(answer["distance"].get<double>(), exact.distance, 0.05 * kVoxel);
    EXPECT_LE((jsonVector(answer["footpoint"]) - exact.footpoint).norm(), 0.1 * kVoxel)
        << point.transpose();
    EXPECT_GE(jsonVector(answer["normal"]).dot(exact.normal), std::cos(1.0 * M_PI / 180.0));
    // Principal curvatures in either order, each within 3%, and e1 along its direction.
    const double k1 = answer["k1"].get<double>(), k2 = answer["k2"].get<double>();
    const Vector3d e1 = jsonVector(answer["tangent"]);
    const bool k1IsTube = std::abs(k1 - exact.tubeCurvature) < std::abs(k2 - exact.tubeCurvature);
    const double tube = k1IsTube ? k1 : k2, parallel = k1IsTube ? k2 : k1;
    EXPECT_NEAR(tube, exact.tubeCurvature, 0.03 * exact.tubeCurvature) << point.transpose();
    EXPECT_NEAR(parallel, exact.parallelCurvature, 0.03 * std::abs(exact.parallelCurvature))
        << point.transpose();
    const double alongParallel = std::abs(e1.dot(exact.parallelDirection));
    EXPECT_NEAR(alongParallel, k1IsTube ? 0.0 : 1.0, 1.0 - std::cos(3.0 * M_PI / 180.0) + 0.03)
        << point.transpose();
    // The SDM form at the query point approximates the exact squared distance to O(h^3).
    const double exactSquared = std::pow(torusAt(point).distance, 2);
    EXPECT_NEAR(answer["squared_distance_estimate"].get<double>(), exactSquared,
                0.05 * kVoxel * kVoxel)
        << point.transpose();
    const nlohmann::json& form = answer["forms"]["sdm"];
    ASSERT_EQ(form["A"].size(), 3u);
    EXPECT_TRUE(form.contains("b") && form.contains("c"));
    EXPECT_FALSE(answer["forms"].contains("pdm"));
  }

  // --form all adds PDM (A = identity) and TDM (A = n n^T).
  const nlohmann::json all = query(path("torus-field.vdb"), points[0], "--form all");
  const Vector3d n = jsonVector(all["normal"]);
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      EXPECT_NEAR(all["forms"]["pdm"]["A"][row][column].get<double>(), row == column ? 1.0 : 0.0,
                  1e-12);
      EXPECT_NEAR(all["forms"]["tdm"]["A"][row][column].get<double>(), n[row] * n[column], 1e-9);
    }
  }
  const CliResult text = run("query " + path("torus-field.vdb") + " 1.37 0.02 0.03 --form all");
  ASSERT_EQ(text.exitCode, 0) << text.err;
  for (const char* word :
       {"distance", "footpoint", "curvatures", "SDM form", "PDM form", "TDM form"}) {
    EXPECT_NE(text.out.find(word), std::string::npos) << word << "\n" << text.out;
  }

  // Beyond the band the field still answers, from a coarse level, pulling toward the torus.
  const nlohmann::json far = query(path("torus-field.vdb"), Vector3d(2.2, 0.1, 0.6));
  EXPECT_GT(far["level"].get<int>(), 0);
  const std::vector<std::string> farFlags = far["flags"];
  EXPECT_NE(std::find(farFlags.begin(), farFlags.end(), "far_field"), farFlags.end());
  EXPECT_GT(far["squared_distance_estimate"].get<double>(), 0.0);

  // info shows the field next to its grids.
  const CliResult info = run("info --json " + path("torus-field.vdb"));
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const auto infoReport = nlohmann::json::parse(info.out);
  ASSERT_TRUE(infoReport.contains("field"));
  EXPECT_EQ(infoReport["field"]["kind"], "surface");
  EXPECT_GE(infoReport["field"]["levels"].size(), 2u);  // info builds and shows every level
  EXPECT_EQ(infoReport["field"]["coarse_levels_built"], true);
  const std::vector<std::string> companions = infoReport["field"]["companion_grids"];
  for (const char* name : {"normal", "k1", "k2", "e1"}) {
    EXPECT_NE(std::find(companions.begin(), companions.end(), name), companions.end()) << name;
  }
  const CliResult infoText = run("info " + path("torus-field.vdb"));
  ASSERT_EQ(infoText.exitCode, 0) << infoText.err;
  EXPECT_NE(infoText.out.find("approximant field"), std::string::npos) << infoText.out;
  EXPECT_NE(infoText.out.find("companion grids"), std::string::npos) << infoText.out;
  // A plain level set has no "field" key.
  const CliResult plain = run("info --json " + torusVdb());
  ASSERT_EQ(plain.exitCode, 0) << plain.err;
  EXPECT_FALSE(nlohmann::json::parse(plain.out).contains("field"));

  // Re-reading a field file keeps the field.
  const CliResult again =
      run("field " + path("torus-field.vdb") + " " + path("again.vdb") + " --json");
  ASSERT_EQ(again.exitCode, 0) << again.err;
  EXPECT_EQ(nlohmann::json::parse(again.out)["input_kind"], "field");
}

TEST_F(FieldCliTest, CurveAndPointFieldsAnswerWithTheirExactGeometry) {
  // A closed polyline sampling the unit circle in the plane z = 0.2.
  d2vdb::Polyline circle;
  circle.closed = true;
  for (int i = 0; i < 720; ++i) {
    const double angle = 2.0 * M_PI * i / 720.0;
    circle.points.emplace_back(std::cos(angle), std::sin(angle), 0.2);
  }
  d2vdb::writePolyline(scratch_ / "circle.json", circle);
  const CliResult built = run("field " + path("circle.json") + " " + path("circle.vdb") +
                              " --resolution 80 --half-width 4 --json");
  ASSERT_EQ(built.exitCode, 0) << built.err;
  const auto report = nlohmann::json::parse(built.out);
  EXPECT_EQ(report["kind"], "curve");
  EXPECT_EQ(report["input_kind"], "polyline");
  const double voxel = report["voxel_size"].get<double>();
  EXPECT_NEAR(voxel, 2.0 / 80.0, 1e-3);  // the circle's longest side over the resolution

  const nlohmann::json answer = query(path("circle.vdb"), Vector3d(0.6, 0.8 + 0.03, 0.21));
  EXPECT_EQ(answer["kind"], "curve");
  EXPECT_EQ(answer["level"], 0);
  const Vector3d origin = jsonVector(answer["origin"]);
  const Vector3d radial = Vector3d(origin.x(), origin.y(), 0).normalized();
  const Vector3d foot = radial + Vector3d(0, 0, 0.2);
  EXPECT_NEAR(answer["distance"].get<double>(), (origin - foot).norm(), 0.05 * voxel);
  EXPECT_LE((jsonVector(answer["footpoint"]) - foot).norm(), 0.05 * voxel);
  EXPECT_NEAR(answer["curvature"].get<double>(), 1.0, 0.02);
  EXPECT_GE(jsonVector(answer["principal_normal"]).dot(-radial), std::cos(2.0 * M_PI / 180.0));
  EXPECT_GE(std::abs(jsonVector(answer["tangent"]).dot(Vector3d::UnitZ().cross(radial))),
            std::cos(2.0 * M_PI / 180.0));

  // Points: the footpoint is the nearest point; every form is |x - q|^2 (A = identity).
  const std::vector<Vector3d> points = {Vector3d(0, 0, 0), Vector3d(1, 0.5, 0), Vector3d(0.3, 1, 1),
                                        Vector3d(-0.5, 0.25, 0.75)};
  d2vdb::writePointSet(scratch_ / "points.xyz", points);
  const CliResult cloud = run("field " + path("points.xyz") + " " + path("points.vdb") +
                              " --voxel-size 0.02 --half-width 5 --json");
  ASSERT_EQ(cloud.exitCode, 0) << cloud.err;
  EXPECT_EQ(nlohmann::json::parse(cloud.out)["kind"], "points");
  const nlohmann::json near = query(path("points.vdb"), Vector3d(0.98, 0.53, 0.04));
  EXPECT_EQ(near["kind"], "points");
  EXPECT_LE((jsonVector(near["footpoint"]) - points[1]).norm(), 0.05 * 0.02);
  const Vector3d nearOrigin = jsonVector(near["origin"]);
  EXPECT_NEAR(near["distance"].get<double>(), (nearOrigin - points[1]).norm(), 0.05 * 0.02);
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      EXPECT_NEAR(near["forms"]["sdm"]["A"][row][column].get<double>(), row == column ? 1.0 : 0.0,
                  1e-12);
    }
  }
}

TEST_F(FieldCliTest, BadInputIsRejectedWithExitCodes) {
  // Missing input, unknown extension, bad options.
  const CliResult missing = run("field " + path("absent.vdb") + " " + path("out.vdb"));
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_NE(missing.err.find("absent.vdb"), std::string::npos) << missing.err;
  EXPECT_EQ(run("field " + path("absent.txt") + " " + path("out.vdb")).exitCode, 2);
  EXPECT_EQ(run("field " + torusVdb()).exitCode, 1);
  EXPECT_EQ(run("field " + torusVdb() + " " + path("out.vdb") + " --half-width 0").exitCode, 1);
  EXPECT_EQ(run("query " + path("absent.vdb") + " 0 0 0").exitCode, 2);
  EXPECT_EQ(run("query " + torusVdb() + " 0 0").exitCode, 1);
  EXPECT_FALSE(fs::exists(scratch_ / "out.vdb"));

  // A slice file with two loops is not one polyline: the message says how many.
  ASSERT_EQ(run("slice " + torusVdb() + " " + path("t.svg") + " --axis z --offset 0 --polylines " +
                path("loops.json") + " -q")
                .exitCode,
            0);
  const CliResult loops = run("field " + path("loops.json") + " " + path("out.vdb"));
  EXPECT_EQ(loops.exitCode, 2);
  EXPECT_NE(loops.err.find("holds 2 polylines"), std::string::npos) << loops.err;

  // A point outside the working domain: exit 2, saying by how much.
  ASSERT_EQ(run("field " + torusVdb() + " " + path("torus-field.vdb") + " -q").exitCode, 0);
  const auto info = nlohmann::json::parse(run("info --json " + path("torus-field.vdb")).out);
  const double domainMaxX = info["field"]["domain"]["max"][0].get<double>();
  const CliResult outside = run("query " + path("torus-field.vdb") + " 100 0 0");
  EXPECT_EQ(outside.exitCode, 2);
  const std::size_t lies = outside.err.find("lies ");
  ASSERT_NE(lies, std::string::npos) << outside.err;
  EXPECT_NEAR(std::stod(outside.err.substr(lies + 5)), 100.0 - domainMaxX, 1e-6) << outside.err;
  EXPECT_NE(outside.err.find("outside"), std::string::npos) << outside.err;

  // A truncated field file is rejected by query, info and field, leaving no output behind.
  const std::string bytes = readWholeFile(scratch_ / "torus-field.vdb");
  {
    std::ofstream out(scratch_ / "cut.vdb", std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  for (const std::string& command :
       {"query " + path("cut.vdb") + " 1.35 0 0", "info " + path("cut.vdb"),
        "field " + path("cut.vdb") + " " + path("out.vdb")}) {
    const CliResult result = run(command);
    EXPECT_EQ(result.exitCode, 2) << command << "\n" << result.err;
    EXPECT_NE(result.err.find("cut.vdb"), std::string::npos) << result.err;
  }
  EXPECT_FALSE(fs::exists(scratch_ / "out.vdb"));

  for (const char* command : {"field --help", "query --help"}) {
    const CliResult help = run(command);
    EXPECT_EQ(help.exitCode, 0) << command;
    EXPECT_NE(help.out.find("Example"), std::string::npos) << command;
  }
}

}  // namespace
