// d2vdb convert on grids from other tools: a fog volume (densities) is refused with the option
// that converts it, and with --iso becomes a level set that `d2vdb mesh` meshes closed.
#include <gtest/gtest.h>
#include <openvdb/tools/LevelSetUtil.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/VdbFile.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;

class ConvertCliTest : public d2vdb::test::CliFixture {
 protected:
  // A sphere of radius 1 as a fog volume named "density", written as another tool would.
  void writeFogSphere() {
    const openvdb::FloatGrid::Ptr fog =
        d2vdb::primitiveLevelSet(d2vdb::Sphere({0, 0, 0}, 1.0), {0.05, 3.0});
    openvdb::tools::sdfToFogVolume(*fog, 0.15f);
    fog->setName("density");
    d2vdb::writeVdb(scratch_ / "fog.vdb", {fog});
  }
};

TEST_F(ConvertCliTest, FogVolumeIsRefusedWithoutIso) {
  writeFogSphere();
  const CliResult result = run("convert " + path("fog.vdb") + " " + path("out.vdb"));
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("fog volume"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("--iso"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(scratch_ / "out.vdb"));
}

TEST_F(ConvertCliTest, FogVolumeAtIsoBecomesAClosedLevelSet) {
  writeFogSphere();
  const CliResult made = run("convert " + path("fog.vdb") + " " + path("out.vdb") +
                             " --grid density --iso 0.5 --json -q");
  ASSERT_EQ(made.exitCode, 0) << made.err;
  const CliResult info = run("info --json " + path("out.vdb"));
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const nlohmann::json grid = nlohmann::json::parse(info.out).at("grids").at(0);
  EXPECT_EQ(grid.at("class"), "level set");
  EXPECT_EQ(grid.at("name"), "surface");
  // density 0.5 lies 0.075 inside the unit sphere: the level set's bounding box spans its
  // radius 0.925 plus the band of 3 voxels.
  const double maxX = grid.at("world_bbox").at("max").at(0).get<double>();
  EXPECT_NEAR(maxX, 0.925 + 0.15, 0.06);
  const CliResult meshed =
      run("mesh " + path("out.vdb") + " " + path("out.obj") + " --check --json -q");
  ASSERT_EQ(meshed.exitCode, 0) << meshed.err;
  const nlohmann::json check = nlohmann::json::parse(meshed.out).at("check");
  EXPECT_TRUE(check.at("closed").get<bool>());
  EXPECT_EQ(check.at("components").get<int>(), 1);
}

TEST_F(ConvertCliTest, NoSurfaceAtIsoIsRefused) {
  writeFogSphere();
  const CliResult result = run("convert " + path("fog.vdb") + " " + path("out.vdb") + " --iso 2");
  EXPECT_EQ(result.exitCode, 2) << result.err;
  EXPECT_NE(result.err.find("no surface at iso-value 2"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(scratch_ / "out.vdb"));
}

}  // namespace
