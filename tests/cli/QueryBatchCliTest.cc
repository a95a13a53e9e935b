// End-to-end tests of `d2vdb query FIELD --points P --out R`: the batch answers equal the
// single-point answers of the same command point by point and the analytic sphere, the output is
// bitwise the same for any --threads, and every bad input is refused with exit code 2 before any
// work, leaving an existing result file as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;
using d2vdb::test::readWholeFile;
using Eigen::Vector3d;

constexpr double kRadius = 0.8;
constexpr double kVoxel = 0.02;

Vector3d jsonVector(const nlohmann::json& value) {
  return {value.at(0).get<double>(), value.at(1).get<double>(), value.at(2).get<double>()};
}

bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

class QueryBatchCliTest : public d2vdb::test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    std::ostringstream primitive;
    primitive << "primitive sphere --center 0,0,0 --radius " << kRadius << " --voxel-size "
              << kVoxel << " " << path("sphere.vdb") << " -q";
    ASSERT_EQ(run(primitive.str()).exitCode, 0);
    ASSERT_EQ(run("field " + path("sphere.vdb") + " " + path("field.vdb") + " -q").exitCode, 0);
    // Points in the band, beyond it inside and outside, and one outside the working domain.
    std::mt19937 random(11);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> near(0.97, 1.03), far(1.2, 1.8), inner(0.2, 0.7);
    for (int i = 0; i < 40; ++i) {
      const Vector3d direction = Vector3d(gauss(random), gauss(random), gauss(random)).normalized();
      const double scale = i < 24 ? near(random) : i < 34 ? far(random) : inner(random);
      points_.push_back(kRadius * scale * direction);
    }
    points_.emplace_back(30.0, 0.0, 0.0);
    std::ostringstream xyz;
    xyz.precision(17);
    xyz << "# query points\n";
    for (const Vector3d& p : points_) xyz << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    write("points.xyz", xyz.str());
  }

  /// The single-point query's JSON answer.
  nlohmann::json single(const Vector3d& point) const {
    std::ostringstream arguments;
    arguments.precision(17);
    arguments << "query " << path("field.vdb") << " --json -- " << point.x() << ' ' << point.y()
              << ' ' << point.z();
    const CliResult result = run(arguments.str());
    EXPECT_EQ(result.exitCode, 0) << result.err;
    return nlohmann::json::parse(result.out);
  }

  std::vector<Vector3d> points_;
};

TEST_F(QueryBatchCliTest, BatchAnswersAreTheSinglePointAnswersAndTheSphere) {
  const CliResult batch = run("query " + path("field.vdb") + " --points " + path("points.xyz") +
                              " --out " + path("answers.csv") + " --json");
  ASSERT_EQ(batch.exitCode, 0) << batch.err;
  const auto report = nlohmann::json::parse(batch.out);
  EXPECT_EQ(report["count"], points_.size());
  EXPECT_EQ(report["outside_domain"], 1);
  EXPECT_EQ(report["answered"], points_.size() - 1);
  EXPECT_EQ(report["kind"], "surface");

  std::stringstream csv(readWholeFile(scratch_ / "answers.csv"));
  std::string line;
  std::getline(csv, line);
  const std::vector<std::string> columns = splitCsv(line);
  const auto column = [&](const std::string& name) {
    const auto at = std::find(columns.begin(), columns.end(), name);
    EXPECT_NE(at, columns.end()) << name;
    return static_cast<std::size_t>(at - columns.begin());
  };
  int beyond = 0;
  for (const Vector3d& point : points_) {
    ASSERT_TRUE(std::getline(csv, line));
    const std::vector<std::string> row = splitCsv(line);
    ASSERT_EQ(row.size(), columns.size());
    const auto value = [&](const std::string& name) {
      return std::strtod(row[column(name)].c_str(), nullptr);
    };
    const auto vector = [&](const std::string& name) {
      return Vector3d(value(name + "_x"), value(name + "_y"), value(name + "_z"));
    };
    EXPECT_TRUE(sameBits(value("x"), point.x()) && sameBits(value("z"), point.z()));
    if (point.norm() > 10.0) {
      EXPECT_EQ(row[column("status")], "outside_domain");
      EXPECT_TRUE(row[column("distance")].empty());
      continue;
    }
    EXPECT_EQ(row[column("status")], "ok");
    // The single query of the same point: the same numbers, bit for bit.
    const nlohmann::json answer = single(point);
    EXPECT_EQ(answer["level"].get<int>(), static_cast<int>(value("level")));
    EXPECT_TRUE(sameBits(answer["distance"].get<double>(), value("distance")));
    EXPECT_TRUE(sameBits(answer["squared_distance_estimate"].get<double>(),
                         value("squared_distance_estimate")));
    for (const char* name : {"origin", "footpoint", "normal", "tangent", "bitangent"}) {
      const Vector3d expected = jsonVector(answer[name]), got = vector(name);
      for (int i = 0; i < 3; ++i) EXPECT_TRUE(sameBits(expected[i], got[i])) << name;
    }
    EXPECT_TRUE(sameBits(answer["k1"].get<double>(), value("k1")));
    EXPECT_TRUE(sameBits(answer["k2"].get<double>(), value("k2")));
    const nlohmann::json& sdm = answer["forms"]["sdm"];
    EXPECT_TRUE(sameBits(sdm["A"][0][1].get<double>(), value("sdm_A_xy")));
    EXPECT_TRUE(sameBits(sdm["A"][2][2].get<double>(), value("sdm_A_zz")));
    EXPECT_TRUE(sameBits(sdm["b"][1].get<double>(), value("sdm_b_y")));
    EXPECT_TRUE(sameBits(sdm["c"].get<double>(), value("sdm_c")));
    const Vector3d weights(value("sdm_weights_1"), value("sdm_weights_2"), value("sdm_weights_3"));
    for (int i = 0; i < 3; ++i)
      EXPECT_TRUE(sameBits(answer["sdm_weights"][i].get<double>(), weights[i]));
    // The analytic sphere: distance |p| - R, footpoint and normal radial, curvatures 1/R.
    const bool band = value("level") == 0;
    beyond += band ? 0 : 1;
    // Beyond the band: ApproximantField::coarseDistanceErrorBound(level).
    const double tolerance =
        band ? 0.05 * kVoxel : std::sqrt(3.0) * kVoxel * (std::ldexp(1.0, int(value("level"))) + 1);
    EXPECT_NEAR(value("distance"), point.norm() - kRadius, tolerance);
    EXPECT_LE((vector("footpoint") - kRadius * point.normalized()).norm(),
              band ? 0.1 * kVoxel : tolerance);
    // Beyond the band the normal points from the footpoint to the point: its angle to the exact
    // normal is bounded by the footpoint's error seen from the point.
    const double depth = std::abs(point.norm() - kRadius);
    const double angle =
        band ? 1.0 * M_PI / 180.0 : std::atan2(tolerance, std::max(depth - tolerance, 0.0));
    EXPECT_GE(vector("normal").dot(point.normalized()), std::cos(angle) - 1e-12);
    EXPECT_NEAR(value("k1"), 1.0 / kRadius, 0.03 / kRadius);
    EXPECT_NEAR(value("k2"), 1.0 / kRadius, 0.03 / kRadius);
  }
  EXPECT_GE(beyond, 10);
}

TEST_F(QueryBatchCliTest, OutputIsBitwiseTheSameForAnyThreadCount) {
  for (const char* name : {"r.csv", "r.ply", "r.json"}) {
    std::string outputs[2];
    for (int threads : {1, 2}) {
      const std::string out = std::to_string(threads) + name;
      ASSERT_EQ(run("query " + path("field.vdb") + " --points " + path("points.xyz") + " --out " +
                    path(out) + " --form all -q --threads " + std::to_string(threads))
                    .exitCode,
                0);
      outputs[threads - 1] = readWholeFile(scratch_ / out);
    }
    EXPECT_FALSE(outputs[0].empty()) << name;
    EXPECT_TRUE(outputs[0] == outputs[1]) << name;
  }
  const auto document = nlohmann::json::parse(readWholeFile(scratch_ / "1r.json"));
  ASSERT_EQ(document["points"].size(), points_.size());
  EXPECT_TRUE(document["points"][0]["forms"].contains("tdm"));
}

TEST_F(QueryBatchCliTest, BadInputIsRefusedBeforeAnyWorkAndTheOutputSurvives) {
  write("answers.csv", "keep me");
  write("nan.xyz", "0 0 1\n0 nan 1\n");
  write("empty.xyz", "# nothing here\n");
  write("answers.txt", "keep me too");
  const std::string field = path("field.vdb"), out = " --out " + path("answers.csv");
  struct Refusal {
    std::string arguments;
    std::string message;
  };
  const std::vector<Refusal> refusals = {
      {field + " --points " + path("absent.xyz") + out, "absent.xyz"},
      {field + " --points " + path("nan.xyz") + out, "nan.xyz"},
      {field + " --points " + path("empty.xyz") + out, "empty.xyz"},
      {field + " --points " + path("points.xyz") + " --out " + path("answers.txt"), "answers.txt"},
      {path("absent.vdb") + " --points " + path("points.xyz") + out, "absent.vdb"},
  };
  for (const Refusal& refusal : refusals) {
    const CliResult result = run("query " + refusal.arguments);
    EXPECT_EQ(result.exitCode, 2) << refusal.arguments << "\n" << result.err;
    EXPECT_NE(result.err.find(refusal.message), std::string::npos) << result.err;
  }
  EXPECT_EQ(readWholeFile(scratch_ / "answers.csv"), "keep me");
  EXPECT_EQ(readWholeFile(scratch_ / "answers.txt"), "keep me too");
  // --points and --out go together, and exclude a point: usage errors.
  EXPECT_EQ(run("query " + field + " --points " + path("points.xyz")).exitCode, 1);
  EXPECT_EQ(run("query " + field + out).exitCode, 1);
  EXPECT_EQ(run("query " + field + " --points " + path("points.xyz") + out + " 0 0 0").exitCode, 1);
  EXPECT_EQ(run("query " + field).exitCode, 2);
  const CliResult help = run("query --help");
  EXPECT_NE(help.out.find("--points"), std::string::npos);
  EXPECT_NE(help.out.find("outside_domain"), std::string::npos);
}

}  // namespace
