// End-to-end tests of `d2vdb mesh` and `d2vdb slice`: outputs, checks, JSON keys, exit codes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/MeshValidation.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;
using d2vdb::test::readWholeFile;

class MeshCliTest : public d2vdb::test::CliFixture {
 protected:
  void SetUp() override {
    d2vdb::test::CliFixture::SetUp();
    const CliResult torus = run("primitive torus --major 1 --minor 0.35 --voxel-size 0.05 " +
                                path("torus.vdb") + " --quiet");
    ASSERT_EQ(torus.exitCode, 0) << torus.err;
  }
};

TEST_F(MeshCliTest, MeshesAndChecksATorus) {
  const CliResult result =
      run("mesh " + path("torus.vdb") + " " + path("torus.ply") + " --check --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  for (const char* key : {"input", "output", "grid", "iso", "vertices", "triangles", "seconds",
                          "extraction_seconds", "check"}) {
    EXPECT_TRUE(report.contains(key)) << key;
  }
  EXPECT_EQ(report["check"]["closed"], true);
  EXPECT_EQ(report["check"]["manifold"], true);
  EXPECT_EQ(report["check"]["oriented"], true);
  EXPECT_EQ(report["check"]["euler_characteristic"], 0);
  EXPECT_EQ(report["check"]["genus"], 1);
  const d2vdb::TriangleMesh mesh = d2vdb::readMesh(scratch_ / "torus.ply");
  EXPECT_EQ(mesh.triangleCount(), report["triangles"].get<std::size_t>());
  EXPECT_TRUE(mesh.hasNormals());
  EXPECT_TRUE(d2vdb::validateMesh(mesh).closed);

  const CliResult text = run("mesh " + path("torus.vdb") + " " + path("torus.stl") +
                             " --iso 0.05 --check --no-normals");
  ASSERT_EQ(text.exitCode, 0) << text.err;
  EXPECT_NE(text.err.find("genus 1"), std::string::npos) << text.err;
  EXPECT_NE(text.err.find("triangles"), std::string::npos) << text.err;
}

TEST_F(MeshCliTest, RejectsBadRequests) {
  const CliResult outside = run("mesh " + path("torus.vdb") + " " + path("out.obj") + " --iso 0.2");
  EXPECT_EQ(outside.exitCode, 2);
  EXPECT_NE(outside.err.find("exceeds by"), std::string::npos) << outside.err;
  EXPECT_FALSE(fs::exists(scratch_ / "out.obj"));
  EXPECT_EQ(run("mesh " + path("torus.vdb") + " " + path("out.xyz")).exitCode, 2);
  EXPECT_EQ(run("mesh " + path("missing.vdb") + " " + path("out.obj")).exitCode, 2);
  const CliResult grid =
      run("mesh " + path("torus.vdb") + " " + path("out.obj") + " --grid nothing");
  EXPECT_EQ(grid.exitCode, 2);
  EXPECT_NE(grid.err.find("surface"), std::string::npos) << grid.err;
  EXPECT_EQ(run("mesh " + path("torus.vdb")).exitCode, 1);
  const CliResult help = run("mesh --help");
  EXPECT_EQ(help.exitCode, 0);
  EXPECT_NE(help.out.find("Example"), std::string::npos);
}

TEST_F(MeshCliTest, SlicesATorusIntoTwoClosedLoops) {
  const CliResult result =
      run("slice " + path("torus.vdb") + " " + path("torus.svg") +
          " --axis z --offset 0.1 --polylines " + path("lines.json") + " --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["lines"], 2);
  EXPECT_EQ(report["closed_lines"], 2);
  EXPECT_EQ(report["axis"], "z");
  EXPECT_EQ(report["plane_axes"], nlohmann::json({"x", "y"}));
  EXPECT_NE(readWholeFile(scratch_ / "torus.svg").find("<svg"), std::string::npos);
  const auto lines = nlohmann::json::parse(readWholeFile(scratch_ / "lines.json"));
  ASSERT_EQ(lines["polylines"].size(), 2u);
  EXPECT_EQ(lines["polylines"][0]["closed"], true);
  EXPECT_GT(lines["polylines"][0]["points"].size(), 10u);

  EXPECT_EQ(run("slice " + path("torus.vdb") + " " + path("x.svg") + " --axis w").exitCode, 1);
  const CliResult help = run("slice --help");
  EXPECT_EQ(help.exitCode, 0);
  EXPECT_NE(help.out.find("Example"), std::string::npos);
}

}  // namespace
