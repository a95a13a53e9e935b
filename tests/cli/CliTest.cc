// End-to-end tests of the d2vdb command: exit codes, messages, and that failures never touch an
// existing output file.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"
#include "d2vdb/core/Version.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/VdbFile.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;
using d2vdb::test::readWholeFile;

const fs::path kSourceDir = D2VDB_SOURCE_DIR;

class CliTest : public d2vdb::test::CliFixture {
 protected:
  /// A closed unit cube as OBJ text (12 triangles, outward winding).
  static std::string cubeObj() {
    return "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
           "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
           "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  }
};

TEST_F(CliTest, VersionAndHelp) {
  const CliResult version = run("--version");
  EXPECT_EQ(version.exitCode, 0);
  EXPECT_NE(version.out.find(d2vdb::kVersion), std::string::npos) << version.out;

  const CliResult help = run("--help");
  EXPECT_EQ(help.exitCode, 0);
  for (const char* subcommand : {"info", "mesh2sdf", "primitive", "convert"}) {
    EXPECT_NE(help.out.find(subcommand), std::string::npos) << subcommand;
    const CliResult subHelp = run(std::string(subcommand) + " --help");
    EXPECT_EQ(subHelp.exitCode, 0) << subcommand << subHelp.err;
    EXPECT_NE(subHelp.out.find("Example"), std::string::npos) << subcommand << subHelp.out;
  }
}

TEST_F(CliTest, UsageErrorsExitWithOne) {
  EXPECT_EQ(run("").exitCode, 1);
  EXPECT_EQ(run("no-such-subcommand").exitCode, 1);
  EXPECT_EQ(run("info").exitCode, 1);  // missing FILE
  const fs::path cube = write("cube.obj", cubeObj());
  EXPECT_EQ(run("mesh2sdf " + path("cube.obj") + " " + path("out.vdb") +
                " --voxel-size 0.1 --resolution 20")
                .exitCode,
            1);  // the two exclude each other
  EXPECT_FALSE(fs::exists(scratch_ / "out.vdb"));
  EXPECT_EQ(
      run("mesh2sdf " + path("cube.obj") + " " + path("out.vdb") + " --voxel-size -1").exitCode, 1);
}

TEST_F(CliTest, BandWithoutASizeHasTheDefaultResolution) {
  // Neither --voxel-size nor --resolution: 256 voxels along the longest side, for every command
  // that builds a band (the unit cube: voxel size 1/256; the unit sphere's box: 2/256).
  write("cube.obj", cubeObj());
  const CliResult mesh =
      run("mesh2sdf " + path("cube.obj") + " " + path("cube.vdb") + " --json -q");
  ASSERT_EQ(mesh.exitCode, 0) << mesh.err;
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(mesh.out).at("voxel_size").get<double>(), 1.0 / 256);
  const CliResult sphere = run("primitive sphere " + path("sphere.vdb") + " --json -q");
  ASSERT_EQ(sphere.exitCode, 0) << sphere.err;
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(sphere.out).at("voxel_size").get<double>(), 2.0 / 256);
}

TEST_F(CliTest, NonexistentInputIsBadInput) {
  const CliResult result = run("info " + path("missing.vdb"));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("missing.vdb"), std::string::npos) << result.err;
}

TEST_F(CliTest, EmptyAndTruncatedVdbAreBadInputAndLeaveOutputUntouched) {
  write("empty.vdb", "");
  const fs::path existing = write("existing.vdb", "precious contents");
  CliResult result = run("convert " + path("empty.vdb") + " " + path("existing.vdb"));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("empty.vdb"), std::string::npos) << result.err;
  EXPECT_EQ(readWholeFile(existing), "precious contents");

  const std::string whole = readWholeFile(kSourceDir / "volumes" / "torus.vdb");
  ASSERT_GT(whole.size(), 1000u);
  for (const double keep : {0.1, 0.5, 0.9}) {
    write("truncated.vdb", whole.substr(0, static_cast<std::size_t>(keep * whole.size())));
    result = run("convert " + path("truncated.vdb") + " " + path("existing.vdb"));
    EXPECT_EQ(result.exitCode, 2) << keep << result.err;
    EXPECT_NE(result.err.find("truncated.vdb"), std::string::npos) << result.err;
    EXPECT_EQ(readWholeFile(existing), "precious contents");
    result = run("info " + path("truncated.vdb"));
    EXPECT_EQ(result.exitCode, 2) << keep << result.err;
  }
  // Nothing but the inputs and the untouched output is left behind (no temporaries).
  std::size_t entries = 0;
  for (const auto& entry : fs::directory_iterator(scratch_)) {
    if (entry.path().filename().string().find("d2vdb-tmp") != std::string::npos) ADD_FAILURE();
    ++entries;
  }
  EXPECT_GE(entries, 3u);
}

TEST_F(CliTest, ObjWithNanIsBadInputNamingTheLine) {
  write("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  const fs::path existing = write("existing.vdb", "precious contents");
  const CliResult result =
      run("mesh2sdf " + path("nan.obj") + " " + path("existing.vdb") + " --voxel-size 0.1");
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("nan.obj"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("3"), std::string::npos) << result.err;  // the line number
  EXPECT_EQ(readWholeFile(existing), "precious contents");
}

TEST_F(CliTest, AbsurdResolutionIsRefusedQuicklyWithAdvice) {
  write("cube.obj", cubeObj());
  const fs::path existing = write("existing.vdb", "precious contents");
  const auto start = std::chrono::steady_clock::now();
  const CliResult result =
      run("mesh2sdf " + path("cube.obj") + " " + path("existing.vdb") + " --resolution 1000000");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("voxel"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("resolution"), std::string::npos) << result.err;
  EXPECT_LT(seconds, 10.0);
  EXPECT_EQ(readWholeFile(existing), "precious contents");
}

TEST_F(CliTest, WideBandsHugeVoxelsAndZeroResolutionAreRefusedClearly) {
  write("cube.obj", cubeObj());
  // A band of 1000 voxels holds ~5e9 voxels at any voxel size: refused at once, saying so.
  CliResult result = run("mesh2sdf " + path("cube.obj") + " " + path("out.vdb") +
                         " --resolution 200 --half-width 1000");
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("no voxel size fits"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("a half-width of at most"), std::string::npos) << result.err;
  EXPECT_EQ(result.err.find("inf"), std::string::npos) << result.err;
  // A voxel far larger than the cube would give an empty level set: refused, nothing written.
  result = run("mesh2sdf " + path("cube.obj") + " " + path("out.vdb") + " --voxel-size 1e300");
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("the level set is empty"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(scratch_ / "out.vdb"));
  result = run("primitive sphere --radius 1 --voxel-size 1e300 " + path("out.vdb"));
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_FALSE(fs::exists(scratch_ / "out.vdb"));
  // Zero resolution: a usage error that names the value, not the range of a double.
  result = run("mesh2sdf " + path("cube.obj") + " " + path("out.vdb") + " --resolution 0");
  EXPECT_EQ(result.exitCode, 1) << result.err;
  EXPECT_NE(result.err.find("must be a positive number, got 0"), std::string::npos) << result.err;
  EXPECT_EQ(result.err.find("1.79"), std::string::npos) << result.err;
}

TEST_F(CliTest, InfoJsonWithNonUtf8MetadataIsValidJson) {
  // Metadata text comes from files and need not be UTF-8: the JSON report replaces bad bytes.
  d2vdb::VdbWriteOptions options;
  options.source = std::string("caf\xe9 \xff.obj");
  d2vdb::writeVdb(scratch_ / "latin1.vdb",
                  {d2vdb::primitiveLevelSet(d2vdb::Sphere({0, 0, 0}, 1.0), {0.25, 3.0})}, options);
  const CliResult result = run("info --json " + path("latin1.vdb"));
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  const std::string source = report.at("grids").at(0).at("metadata").at("d2vdb_source");
  EXPECT_EQ(source, "caf\xef\xbf\xbd \xef\xbf\xbd.obj");  // U+FFFD twice
  EXPECT_EQ(run("info " + path("latin1.vdb")).exitCode, 0);
}

TEST_F(CliTest, MeshToLevelSetThenInfoAsJson) {
  write("cube.obj", cubeObj());
  const CliResult made = run("mesh2sdf " + path("cube.obj") + " " + path("cube.vdb") +
                             " --voxel-size 0.05 --json --quiet");
  ASSERT_EQ(made.exitCode, 0) << made.err;
  const nlohmann::json summary = nlohmann::json::parse(made.out);
  EXPECT_TRUE(summary.at("mesh").at("closed").get<bool>());
  EXPECT_GT(summary.at("active_voxels").get<long>(), 0);

  const CliResult info = run("info --json " + path("cube.vdb"));
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const nlohmann::json report = nlohmann::json::parse(info.out);
  ASSERT_EQ(report.at("grids").size(), 1u);
  const nlohmann::json& grid = report.at("grids").at(0);
  EXPECT_EQ(grid.at("name"), "surface");
  EXPECT_EQ(grid.at("class"), "level set");
  EXPECT_EQ(grid.at("active_voxels"), summary.at("active_voxels"));
  EXPECT_NEAR(grid.at("voxel_size").at(0).get<double>(), 0.05, 1e-9);
  // The cube spans [0,1]^3: its world bounding box covers it, padded by about the band.
  EXPECT_LT(grid.at("world_bbox").at("min").at(0).get<double>(), 0.0);
  EXPECT_GT(grid.at("world_bbox").at("max").at(0).get<double>(), 1.0);
}

TEST_F(CliTest, MeshInfoReportsOpenMesh) {
  // A single square made of two triangles: open, one boundary loop of four edges.
  write("square.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  const CliResult info = run("info --json " + path("square.obj"));
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const nlohmann::json report = nlohmann::json::parse(info.out);
  EXPECT_EQ(report.at("triangles"), 2);
  EXPECT_EQ(report.at("closed"), false);
  EXPECT_EQ(report.at("boundary_loops"), 1);
  EXPECT_EQ(report.at("boundary_edges"), 4);
  EXPECT_NEAR(report.at("surface_area").get<double>(), 1.0, 1e-12);
}

TEST_F(CliTest, PrimitiveSphereIsDeterministicAcrossThreadCounts) {
  const CliResult one =
      run("primitive sphere --radius 1 --voxel-size 0.05 --threads 1 " + path("one.vdb"));
  ASSERT_EQ(one.exitCode, 0) << one.err;
  const CliResult two =
      run("primitive sphere --radius 1 --voxel-size 0.05 --threads 2 " + path("two.vdb"));
  ASSERT_EQ(two.exitCode, 0) << two.err;
  // OpenVDB stamps every file with a random 36-character UUID near its start; everything else
  // (metadata, topology, values) must be byte-identical.
  const std::string a = readWholeFile(scratch_ / "one.vdb");
  const std::string b = readWholeFile(scratch_ / "two.vdb");
  ASSERT_EQ(a.size(), b.size());
  std::size_t firstDifference = a.size(), lastDifference = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] != b[i]) {
      firstDifference = std::min(firstDifference, i);
      lastDifference = i;
    }
  }
  if (firstDifference < a.size()) {
    EXPECT_LT(lastDifference - firstDifference, 36u) << "files differ beyond the UUID";
    EXPECT_LT(lastDifference, 64u) << "files differ beyond the header";
  }

  const CliResult info = run("info --json " + path("one.vdb"));
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const nlohmann::json grid = nlohmann::json::parse(info.out).at("grids").at(0);
  // Sphere of radius 1 at voxel 0.05: 20 voxels radius; band of 2*3 voxels around the surface
  // holds about 4*pi*20^2*6 = 30159 voxels.
  const double expected = 4.0 * 3.14159265358979 * 400.0 * 6.0;
  EXPECT_NEAR(grid.at("active_voxels").get<double>(), expected, 0.05 * expected);
}

TEST_F(CliTest, ConvertRoundTripsBundledVolume) {
  const CliResult result = run("convert '" + (kSourceDir / "volumes" / "torus.vdb").string() +
                               "' " + path("copy.vdb") + " --name copied");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const CliResult original =
      run("info --json '" + (kSourceDir / "volumes" / "torus.vdb").string() + "'");
  const CliResult copy = run("info --json " + path("copy.vdb"));
  ASSERT_EQ(copy.exitCode, 0) << copy.err;
  const nlohmann::json a = nlohmann::json::parse(original.out).at("grids").at(0);
  const nlohmann::json b = nlohmann::json::parse(copy.out).at("grids").at(0);
  EXPECT_EQ(b.at("name"), "copied");
  EXPECT_EQ(a.at("active_voxels"), b.at("active_voxels"));
  EXPECT_EQ(a.at("index_bbox"), b.at("index_bbox"));
  EXPECT_EQ(b.at("metadata").at("creator"), std::string("d2vdb ") + d2vdb::kVersion);
}

}  // namespace
