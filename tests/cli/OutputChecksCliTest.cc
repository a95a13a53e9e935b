// End-to-end tests of what every d2vdb sub-command checks before it starts working: its output
// files (directory, extension, two outputs on one file), its --init names, its missing arguments,
// and values that OpenVDB cannot represent; and that the reports, not warnings, carry the counts
// of routine corrections.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/PolylineFile.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"
#include "field/PolycubeMeshes.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;

const std::string kTorus = "'" + std::string(D2VDB_SOURCE_DIR) + "/volumes/torus.vdb'";

class OutputChecksCliTest : public d2vdb::test::CliFixture {
 protected:
  /// Runs `arguments` and expects exit code 2 with every one of `needles` in the message.
  void expectRefused(const std::string& arguments, const std::vector<std::string>& needles) {
    const CliResult result = run(arguments + " -q");
    EXPECT_EQ(result.exitCode, 2) << arguments << ": " << result.err;
    for (const std::string& needle : needles) {
      EXPECT_NE(result.err.find(needle), std::string::npos)
          << arguments << ": '" << needle << "' not in: " << result.err;
    }
  }
};

TEST_F(OutputChecksCliTest, OutputInAMissingDirectoryIsRefusedBeforeTheInputIsRead) {
  // Every input here is missing too: the error names the output, so it came first.
  const std::string missing = path("missing.obj");
  const std::string out = path("ok.json");
  const std::string nodir = file("nodir").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"mesh2sdf " + missing + " '" + nodir + "/d4.vdb'", "output"},
      {"primitive sphere '" + nodir + "/s.vdb'", "output"},
      {"convert " + missing + " '" + nodir + "/c.vdb'", "output"},
      {"field " + missing + " '" + nodir + "/f.vdb'", "output"},
      {"mesh " + missing + " '" + nodir + "/m.obj'", "output"},
      {"slice " + missing + " '" + nodir + "/s.svg'", "output"},
      {"slice " + missing + " " + path("s.svg") + " --polylines '" + nodir + "/p.json'",
       "--polylines"},
      {"fit-curve --target " + missing + " --out '" + nodir + "/c.json'", "--out"},
      {"fit-curve --target " + missing + " --out " + out + " --svg '" + nodir + "/c.svg'", "--svg"},
      {"fit-curve --target " + missing + " --out " + out + " --plot '" + nodir + "/p.svg'",
       "--plot"},
      {"fit-surface --target " + missing + " --out " + out + " --mesh '" + nodir + "/m.ply'",
       "--mesh"},
      {"fit-surface --target " + missing + " --out " + out + " --rulings '" + nodir + "/r.json'",
       "--rulings"},
      {"fit-surface --target " + missing + " --out " + out + " --plot '" + nodir + "/p.svg'",
       "--plot"},
      {"hausdorff " + missing + " " + missing + " --svg '" + nodir + "/h.svg'", "--svg"},
      {"smooth " + missing + " '" + nodir + "/s.ply'", "output"},
      {"support " + missing + " --out '" + nodir + "/s.json'", "--out"},
      {"offset " + missing + " '" + nodir + "/o.obj' --distance 0.1", "output"},
  };
  for (const auto& [arguments, option] : cases) {
    expectRefused(arguments,
                  {option + " '" + nodir + "/", "directory '" + nodir + "' does not exist"});
  }
  EXPECT_FALSE(fs::exists(file("nodir")));
  EXPECT_FALSE(fs::exists(file("ok.json")));
  EXPECT_FALSE(fs::exists(file("s.svg")));
}

TEST_F(OutputChecksCliTest, OutputWhoseExtensionIsNotWhatIsWrittenIsRefused) {
  const std::string missing = path("missing.obj");
  const std::string out = path("ok.json");
  // What is written decides the extensions; the message names the option and lists them.
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"mesh2sdf " + missing + " " + path("x.obj"), {"output", "x.obj", ".vdb"}},
      {"mesh2sdf " + missing + " " + path("noext"), {"output", "has no extension", ".vdb"}},
      {"primitive sphere " + path("s.ply"), {"output", ".vdb"}},
      {"convert " + missing + " " + path("c.json"), {"output", ".vdb"}},
      {"field " + missing + " " + path("f.obj"), {"output", ".vdb"}},
      {"mesh " + missing + " " + path("m.vdb"), {"output", ".obj, .ply or .stl"}},
      {"slice " + missing + " " + path("s.png"), {"output", ".svg"}},
      {"slice " + missing + " " + path("s.svg") + " --polylines " + path("p.txt"),
       {"--polylines", ".json"}},
      {"fit-curve --target " + missing + " --out " + path("c.vdb"), {"--out", ".json"}},
      {"fit-curve --target " + missing + " --out " + out + " --plot " + path("p.png"),
       {"--plot", ".svg"}},
      {"fit-surface --target " + missing + " --out " + out + " --mesh " + path("x.xyz"),
       {"--mesh", ".obj or .ply"}},
      {"fit-surface --target " + missing + " --out " + out + " --mesh " + path("x.stl"),
       {"--mesh", "STL cannot hold"}},
      {"hausdorff " + missing + " " + missing + " --svg " + path("h.json"), {"--svg", ".svg"}},
      {"smooth " + missing + " " + path("s.off"), {"output", ".obj, .ply or .stl"}},
      {"smooth " + missing + " " + path("s.obj") + " --curvature",
       {"output", ".ply", "--curvature"}},
      {"support " + missing + " --out " + path("s.txt"), {"--out", ".json"}},
      {"offset " + missing + " " + path("o.xyz") + " --distance 0.1",
       {"output", ".obj, .ply, .stl or .vdb"}},
  };
  for (const auto& [arguments, needles] : cases) expectRefused(arguments, needles);
  for (const char* name : {"x.obj", "noext", "s.ply", "ok.json", "x.xyz", "s.obj", "o.xyz"}) {
    EXPECT_FALSE(fs::exists(file(name))) << name;
  }
  // Extensions are compared without regard to case.
  const CliResult upper = run("primitive sphere " + path("S.VDB") + " --resolution 16 -q");
  EXPECT_EQ(upper.exitCode, 0) << upper.err;
  EXPECT_TRUE(fs::exists(file("S.VDB")));
}

TEST_F(OutputChecksCliTest, DirectoriesAndSharedNamesAreRefused) {
  fs::create_directory(file("dir"));
  expectRefused("primitive sphere " + path("dir"), {"output", "is a directory"});
  write("plain.txt", "not a directory\n");
  expectRefused("primitive sphere '" + file("plain.txt").string() + "/s.vdb'",
                {"output", "is not a directory"});
  // Two outputs of one command on the same file, also when spelt differently.
  expectRefused("fit-surface --target " + kTorus + " --out " + path("a.json") + " --rulings '" +
                    file("dir").string() + "/../a.json'",
                {"--out and --rulings both name"});
  EXPECT_FALSE(fs::exists(file("a.json")));
}

TEST_F(OutputChecksCliTest, CleanMeshesGetNoWarningTheCorrectionsAreReported) {
  // Polycubes are closed and clean, yet OpenVDB misjudges some voxels at their concave corners:
  // that is the sign check's routine work, counted in the report, not a warning.
  std::size_t corrected = 0;
  for (int genus = 0; genus <= 3; ++genus) {
    d2vdb::test::PolycubeSpec spec;
    spec.genus = genus;
    spec.seed = static_cast<std::uint32_t>(11 + genus);
    const std::string name = "polycube" + std::to_string(genus);
    d2vdb::writeMesh(file(name + ".obj"), d2vdb::test::makePolycubeMesh(spec));
    const CliResult quiet =
        run("mesh2sdf " + path(name + ".obj") + " " + path(name + ".vdb") + " --resolution 48 -q");
    ASSERT_EQ(quiet.exitCode, 0) << quiet.err;
    EXPECT_EQ(quiet.err, "") << genus;
    const CliResult json = run("mesh2sdf " + path(name + ".obj") + " " + path(name + ".vdb") +
                               " --resolution 48 --json -q");
    ASSERT_EQ(json.exitCode, 0) << json.err;
    const nlohmann::json report = nlohmann::json::parse(json.out);
    EXPECT_TRUE(report.at("warnings").empty()) << report.at("warnings").dump();
    corrected += report.at("signs").at("corrected_voxels").get<std::size_t>();
    // The text summary says it too.
    const CliResult text =
        run("mesh2sdf " + path(name + ".obj") + " " + path(name + ".vdb") + " --resolution 48");
    EXPECT_NE(
        text.err.find(std::to_string(report.at("signs").at("corrected_voxels").get<std::size_t>()) +
                      " voxels of OpenVDB's conversion corrected"),
        std::string::npos)
        << text.err;
    EXPECT_EQ(text.err.find("warning"), std::string::npos) << text.err;
  }
  EXPECT_GT(corrected, 0u);
  // A field of a mesh reports the signs of its level set the same way.
  const CliResult field = run("field " + path("polycube1.obj") + " " + path("field.vdb") +
                              " --resolution 48 --json -q");
  ASSERT_EQ(field.exitCode, 0) << field.err;
  EXPECT_EQ(field.err, "");
  const nlohmann::json report = nlohmann::json::parse(field.out);
  EXPECT_EQ(report.at("signs").at("method"), "closest feature");
  EXPECT_TRUE(report.at("warnings").empty()) << report.at("warnings").dump();
}

TEST_F(OutputChecksCliTest, EveryVdbWriterRecordsTheDistanceKindAndTheExactHalfWidth) {
  ASSERT_EQ(
      run("primitive sphere " + path("s.vdb") + " --resolution 32 --half-width 3 -q").exitCode, 0);
  ASSERT_EQ(run("convert " + path("s.vdb") + " " + path("c.vdb") + " -q").exitCode, 0);
  ASSERT_EQ(run("field " + kTorus + " " + path("f.vdb") + " -q").exitCode, 0);
  const std::vector<Eigen::Vector3d> points = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0.5, 0),
                                               Eigen::Vector3d(0.3, 1, 1)};
  d2vdb::writePointSet(file("p.xyz"), points);
  ASSERT_EQ(run("field " + path("p.xyz") + " " + path("p.vdb") + " --voxel-size 0.05 -q").exitCode,
            0);
  for (const auto& [name, kind] : std::vector<std::pair<std::string, std::string>>{
           {"s.vdb", "signed"}, {"c.vdb", "signed"}, {"f.vdb", "signed"}, {"p.vdb", "unsigned"}}) {
    const auto grids = d2vdb::readAllGrids(file(name));
    ASSERT_FALSE(grids.empty());
    const openvdb::GridBase& grid = *grids.front();
    const auto distance = grid.getMetadata<openvdb::StringMetadata>(d2vdb::kDistanceKindMetadata);
    ASSERT_TRUE(distance) << name;
    EXPECT_EQ(distance->value(), kind) << name;
    const auto halfWidth = grid.getMetadata<openvdb::DoubleMetadata>(d2vdb::kHalfWidthMetadata);
    ASSERT_TRUE(halfWidth) << name;
    EXPECT_EQ(halfWidth->value(), 3.0) << name;  // exactly: the option, not background / voxel
  }
}

TEST_F(OutputChecksCliTest, NamedInitialShapesAndMissingArgumentsAreExplained) {
  write("curve.json", R"({"type": "polyline", "version": 1, "dimension": 2,
                          "points": [[0, 0], [1, 0.5], [2, 0]]})");
  expectRefused("fit-surface --target " + kTorus + " --init sphere --out " + path("o.json"),
                {"--init 'sphere' is not plane, cylinder or torus", "no file of that name"});
  expectRefused(
      "fit-curve --target " + path("curve.json") + " --init sphere --out " + path("o.json"),
      {"--init 'sphere' is not circle, ellipse or polyline", "no file of that name"});
  EXPECT_FALSE(fs::exists(file("o.json")));
  const CliResult hausdorff = run("hausdorff " + path("curve.json"));
  EXPECT_EQ(hausdorff.exitCode, 1);
  EXPECT_NE(hausdorff.err.find("missing b: Shape B"), std::string::npos) << hausdorff.err;
}

TEST_F(OutputChecksCliTest, ValuesOpenVdbCannotRepresentAreRefusedUpFront) {
  d2vdb::writePointSet(file("p.xyz"), {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0.5, 0),
                                       Eigen::Vector3d(0.3, 1, 1)});
  // Voxels below OpenVDB's smallest transform: asked for, or from a tiny shape's resolution.
  expectRefused("field " + path("p.xyz") + " " + path("p.vdb") + " --voxel-size 1e-6",
                {"voxel size 1e-06 is below 1.5e-05"});
  expectRefused("primitive sphere " + path("s.vdb") + " --radius 1e-30", {"is below 1.5e-05"});
  EXPECT_FALSE(fs::exists(file("p.vdb")));
  EXPECT_FALSE(fs::exists(file("s.vdb")));
  // The field of a curve is an unsigned distance: no level set to offset.
  d2vdb::Polyline line;
  line.points = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 0)};
  d2vdb::writePolyline(file("line.json"), line);
  ASSERT_EQ(
      run("field " + path("line.json") + " " + path("line.vdb") + " --resolution 32 -q").exitCode,
      0);
  expectRefused(
      "offset " + path("line.vdb") + " " + path("o.obj") + " --distance 0.1 --method levelset",
      {"is not a level set", "unknown"});
  // An offset that leaves the field's working domain: nothing to fit there.
  expectRefused(
      "fit-surface --target " + kTorus + " --init torus --offset 1e9 --out " + path("o.json"),
      {"--offset 1e+09 reaches beyond the target's working domain", "--padding"});
  EXPECT_FALSE(fs::exists(file("o.obj")));
  EXPECT_FALSE(fs::exists(file("o.json")));
}

}  // namespace
