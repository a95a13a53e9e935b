// The memory and output budgets end to end: absurd options on small inputs are refused with exit
// code 2 before anything is allocated or written, naming the option and the value that would
// fit, and existing output files keep their content; the options that set the budgets; and the
// estimates against the sizes really written on small cases.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;
using d2vdb::test::readWholeFile;
using d2vdb::test::writeWholeFile;

class BudgetCliTest : public d2vdb::test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    // z = xy over [0, 1]^2, an exact surface target (no field to build).
    writeWholeFile(file("hp.json"),
                   R"({"type": "bspline_surface", "version": 1, "degree_u": 1, "degree_v": 1,
                       "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
                       "control_points": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]})");
    // The unit sphere's support function, h = 1 = sqrt(4 pi) Y_0^0.
    writeWholeFile(file("sf.json"),
                   R"({"type": "support_function", "version": 1,
                       "basis": "real_spherical_harmonics", "degree": 0,
                       "coefficients": [3.5449077018110318], "domain": {"kind": "sphere"}})");
    // A 12-triangle cube.
    writeWholeFile(file("small.obj"),
                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                   "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                   "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n");
  }

  // Writes "old" to each of `names`, runs `arguments`, and checks exit code 2, that stderr names
  // every string of `named`, and that every file still holds "old" (and no other file appeared).
  void expectRefused(const std::string& arguments, const std::vector<std::string>& names,
                     const std::vector<std::string>& named) {
    for (const std::string& name : names) writeWholeFile(file(name), "old");
    const auto before = fileCount();
    const CliResult result = run(arguments);
    EXPECT_EQ(result.exitCode, 2) << arguments << "\n" << result.err;
    for (const std::string& text : named) {
      EXPECT_NE(result.err.find(text), std::string::npos)
          << arguments << ": no '" << text << "' in\n"
          << result.err;
    }
    for (const std::string& name : names) EXPECT_EQ(readWholeFile(file(name)), "old") << name;
    EXPECT_EQ(fileCount(), before) << arguments;  // nothing else written
  }

  // Files in the scratch directory besides the captured stdout and stderr.
  std::size_t fileCount() const {
    std::size_t count = 0;
    for (const auto& entry : fs::directory_iterator(scratch_)) {
      if (entry.path().filename().string().rfind("cli.", 0) != 0) ++count;
    }
    return count;
  }
};

TEST_F(BudgetCliTest, RulingsThatWouldNotFitAreRefusedBeforeTheFitAndReplaceNothing) {
  // 100 x 100 ruled control points, 1000 rulings per span: 9.6 million rulings, a 3.2 GB file.
  expectRefused(
      "fit-surface --target " + path("hp.json") + " --init plane --ruled --rulings " +
          path("R.json") + " --ruling-samples 1000 --ctrl 100,100 --out " + path("out.json"),
      {"out.json", "R.json"}, {"--ruling-samples 1000", "--max-output", "use --ruling-samples "});
}

TEST_F(BudgetCliTest, SensorsAndControlPointsThatWouldNotFitAreRefused) {
  // 100 x 100 control points with 100^2 sensors per knot cell: 94 million sensors, about 96 GB.
  expectRefused("fit-surface --target " + path("hp.json") + " --ctrl 100,100 --sensors 100 --out " +
                    path("out.json"),
                {"out.json"}, {"--sensors", "--max-memory", "use --sensors 40 or fewer"});
  // 60 x 60 control points need about 0.5 GB (518 MB measured): within the default budget, but
  // not within 256 MB, where no sensor count helps and fewer control points do.
  expectRefused("fit-surface --target " + path("hp.json") + " --ctrl 60,60 --out " +
                    path("out.json") + " --max-memory 256M",
                {"out.json"}, {"--max-memory", "fewer control points (--ctrl), about "});
}

TEST_F(BudgetCliTest, AWideFieldBandIsRefusedWhenItsMemoryDoesNotFit) {
  // 79 million estimated voxels at 150 bytes each: 11.9 GB, under the voxel limit and the
  // default 16 GiB, refused under a budget of 4 GB, where the ball of 200 voxels alone does not
  // fit, with the half-width that does.
  expectRefused("field " + path("small.obj") + " " + path("f.vdb") +
                    " --resolution 64 --half-width 200 --padding 50 --max-memory 4G",
                {"f.vdb"},
                {"--max-memory", "no voxel size fits", "a half-width of at most 125 voxels"});
  // A narrower band that a coarser voxel fits: the message names that voxel size.
  expectRefused("field " + path("small.obj") + " " + path("f.vdb") +
                    " --resolution 64 --half-width 20 --max-memory 100M",
                {"f.vdb"}, {"--max-memory", "a voxel size of at least"});
}

TEST_F(BudgetCliTest, SupportOffsetsThatWouldNotFitAreRefused) {
  // A level set of 5.2 million triangles: about 2.1 GB for the tessellation and its conversion.
  expectRefused("offset " + path("sf.json") + " " + path("o.vdb") +
                    " --distance 0.1 --subdivisions 9 --resolution 1000 --max-memory 1G",
                {"o.vdb"}, {"--subdivisions 9", "--max-memory", "use --subdivisions "});
  // Two OBJ offsets at 9 subdivisions: 2 x 0.54 GB estimated (2 x 452 MB measured).
  expectRefused("offset " + path("sf.json") + " " + path("o.obj") +
                    " --distance 0.1 --distance 0.2 --subdivisions 9",
                {"o_d0.1.obj", "o_d0.2.obj"},
                {"2 offsets", "--max-output", "use --subdivisions 8 or fewer"});
}

TEST_F(BudgetCliTest, ASmoothTessellationThatWouldNotFitIsRefused) {
  const std::string bunny = std::string("'") + D2VDB_SOURCE_DIR + "/volumes/bunny.obj'";
  // 3674 faces x 4^7: 60 million triangles, about 6.6 GB of OBJ.
  expectRefused("smooth " + bunny + " " + path("s.obj") + " --lod 7 --max-bidegree 12", {"s.obj"},
                {"--lod", "--max-output", "use --lod 5 or lower"});
}

TEST_F(BudgetCliTest, BudgetOptionsAreGlobalAndZeroMeansNoLimit) {
  // The cube at --lod 2: 192 triangles, about 5.4 kB of binary PLY estimated. The options go
  // before or after the sub-command, like --json; a bad value is a usage error naming it.
  const std::string smooth = "smooth " + path("small.obj") + " " + path("s.ply") + " --lod 2 -q";
  EXPECT_EQ(run("--max-output 2k " + smooth).exitCode, 2);
  EXPECT_FALSE(fs::exists(file("s.ply")));
  EXPECT_EQ(run(smooth + " --max-output 2k").exitCode, 2);
  EXPECT_EQ(run(smooth + " --max-output 0").exitCode, 0);
  const auto written = static_cast<double>(fs::file_size(file("s.ply")));
  EXPECT_EQ(run(smooth + " --max-memory 0 --max-output 1GiB").exitCode, 0);
  // The limit is the estimate: just above it passes, just below it is refused.
  const CliResult refused = run(smooth + " --max-output " + std::to_string(int(written)));
  EXPECT_EQ(refused.exitCode, 2) << refused.err;  // the estimate adds the 512-byte header bound
  EXPECT_EQ(run(smooth + " --max-output " + std::to_string(int(written) + 512)).exitCode, 0);
  const CliResult bad = run(smooth + " --max-memory 12Q");
  EXPECT_EQ(bad.exitCode, 1);
  EXPECT_NE(bad.err.find("--max-memory"), std::string::npos) << bad.err;
  const CliResult help = run("--help");
  EXPECT_NE(help.out.find("--max-memory"), std::string::npos);
  EXPECT_NE(help.out.find("--max-output"), std::string::npos);
}

TEST_F(BudgetCliTest, RulingsEstimateBoundsTheFileWritten) {
  // The --rulings estimate (330 bytes a ruling) against a real rulings file: above it, and
  // within 1.5 times it.
  const CliResult result = run("fit-surface --target " + path("hp.json") +
                               " --init plane --ruled --degree 1,3 --ctrl 3,6 --iterations 1"
                               " --ruling-samples 20 --out " +
                               path("fit.json") + " --rulings " + path("r.json") + " --json -q");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  const double count = report["rulings"]["count"].get<double>();
  EXPECT_EQ(count, (3 * 21 + 1) * 2);  // (v spans x (samples + 1) + 1) x u spans
  EXPECT_EQ(report["rulings"]["file"], file("r.json").string());
  const double real = static_cast<double>(fs::file_size(file("r.json")));
  EXPECT_GE(330.0 * count, real);
  EXPECT_LE(330.0 * count, 1.5 * real);
  // Only the outputs are in the directory: the temporaries were renamed.
  for (const auto& entry : fs::directory_iterator(scratch_)) {
    EXPECT_EQ(entry.path().filename().string().find("d2vdb-set"), std::string::npos)
        << entry.path();
  }
}

}  // namespace
