// End-to-end tests of `d2vdb support`, `d2vdb offset` and `d2vdb info` on support-function files:
// an ellipsoid mesh fitted and offset against the exact ellipsoid, a hyperboloid patch, the
// level-set method, and the error paths (exit code 2, nothing written).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/CliRunner.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/support/SphericalTriangulation.h"
#include "support/SupportTestSupport.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::CliResult;

class SupportCliTest : public d2vdb::test::CliFixture {
 protected:
  bool exists(const std::string& name) const { return fs::exists(file(name)); }

  // The ellipsoid (2, 1.5, 1) as a mesh: a geodesic sphere mapped through x_h with exact normals.
  std::string ellipsoidMesh(int subdivisions = 4) const {
    const d2vdb::test::Ellipsoid ellipsoid;
    const d2vdb::SphericalTriangulation sphere = d2vdb::geodesicSphere(subdivisions);
    d2vdb::TriangleMesh mesh;
    for (const Eigen::Vector3d& n : sphere.normals) {
      mesh.positions.push_back(ellipsoid.point(n).cast<float>());
      mesh.normals.push_back(n.cast<float>());
    }
    for (const auto& t : sphere.triangles) mesh.triangles.push_back({t[0], t[1], t[2]});
    d2vdb::writeMesh(file("ellipsoid.obj"), mesh);
    return path("ellipsoid.obj");
  }
};

TEST_F(SupportCliTest, FitsAnEllipsoidAndOffsetsItExactly) {
  const CliResult fitted =
      run("support " + ellipsoidMesh() + " --degree 14 --out " + path("e.json") + " --json");
  ASSERT_EQ(fitted.exitCode, 0) << fitted.err;
  const nlohmann::json report = nlohmann::json::parse(fitted.out);
  EXPECT_TRUE(report.at("regular").get<bool>());
  EXPECT_EQ(report.at("signs"), "convex");
  EXPECT_EQ(report.at("domain"), "sphere");
  EXPECT_EQ(report.at("input_kind"), "mesh");
  EXPECT_NEAR(report.at("safe_offset").at("min").get<double>(), -0.5, 2e-3);  // -c^2 / a
  EXPECT_TRUE(report.at("safe_offset").at("max").is_null());                  // unbounded
  EXPECT_NEAR(report.at("volume").get<double>(), 4.0 * d2vdb::kPi, 1e-3);
  EXPECT_LT(report.at("fit").at("max_residual").get<double>(), 2e-4);
  ASSERT_TRUE(exists("e.json"));

  const CliResult offset = run("offset " + path("e.json") + " " + path("o.obj") +
                               " --distance -0.3 --distance 0.25 --subdivisions 4 --json");
  ASSERT_EQ(offset.exitCode, 0) << offset.err;
  const nlohmann::json outputs = nlohmann::json::parse(offset.out).at("outputs");
  ASSERT_EQ(outputs.size(), 2u);
  const d2vdb::test::Ellipsoid ellipsoid;
  for (const auto& [name, d] :
       {std::pair<std::string, double>{"o_d-0.3.obj", -0.3}, {"o_d0.25.obj", 0.25}}) {
    ASSERT_TRUE(exists(name)) << name;
    const d2vdb::TriangleMesh mesh = d2vdb::readMesh(file(name));
    EXPECT_EQ(mesh.vertexCount(), 2562u);
    double worst = 0.0;
    for (const Eigen::Vector3f& p : mesh.positions) {
      worst = std::max(
          worst, std::abs(d2vdb::test::signedDistanceToEllipsoid(ellipsoid, p.cast<double>()) - d));
    }
    EXPECT_LT(worst, 2e-4) << name;  // the fit at L = 14 plus float output
  }

  const CliResult info = run("info " + path("e.json") + " --json");
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const nlohmann::json described = nlohmann::json::parse(info.out);
  EXPECT_EQ(described.at("kind"), "support_function");
  EXPECT_EQ(described.at("degree"), 14);
  EXPECT_NEAR(described.at("safe_offset").at("min").get<double>(), -0.5, 2e-3);
}

TEST_F(SupportCliTest, HyperboloidPatchIsFittedOverItsGaussImage) {
  d2vdb::writeMesh(file("hyperboloid.obj"), d2vdb::test::hyperboloidPatch(64, 21, 0.5));
  const CliResult fitted = run("support " + path("hyperboloid.obj") + " --degree 16 --out " +
                               path("h.json") + " --json");
  ASSERT_EQ(fitted.exitCode, 0) << fitted.err;
  const nlohmann::json report = nlohmann::json::parse(fitted.out);
  EXPECT_EQ(report.at("input_kind"), "mesh patch");
  EXPECT_EQ(report.at("domain"), "patch");
  EXPECT_EQ(report.at("signs"), "saddle");
  EXPECT_NEAR(report.at("safe_offset").at("min").get<double>(), -1.0, 1e-3);
  EXPECT_NEAR(report.at("safe_offset").at("max").get<double>(), 1.0, 1e-3);
  const CliResult offset =
      run("offset " + path("h.json") + " " + path("h-out.obj") + " --distance 0.1");
  ASSERT_EQ(offset.exitCode, 0) << offset.err;
  EXPECT_TRUE(exists("h-out.obj"));
  const CliResult tooFar =
      run("offset " + path("h.json") + " " + path("far.obj") + " --distance 1.5");
  EXPECT_EQ(tooFar.exitCode, 2);
  EXPECT_NE(tooFar.err.find("safe range"), std::string::npos) << tooFar.err;
  EXPECT_FALSE(exists("far.obj"));
}

// Level sets and fields are fitted from their band's footpoints and normals: a sphere's level
// set (voxel 0.05) against the exact sphere, and the same level set stored as a field.
TEST_F(SupportCliTest, FitsLevelSetsAndFieldsFromTheirBand) {
  const Eigen::Vector3d center(0.1, -0.2, 0.3);
  ASSERT_EQ(
      run("primitive sphere --center 0.1,-0.2,0.3 --radius 1 --voxel-size 0.05 " + path("s.vdb"))
          .exitCode,
      0);
  ASSERT_EQ(run("field " + path("s.vdb") + " " + path("f.vdb")).exitCode, 0);
  std::vector<double> volumes;
  for (const auto& [file, kind] :
       {std::pair<std::string, std::string>{"s.vdb", "level set"}, {"f.vdb", "field"}}) {
    const CliResult fitted =
        run("support " + path(file) + " --degree 6 --out " + path(file + ".json") + " --json");
    ASSERT_EQ(fitted.exitCode, 0) << fitted.err;
    const nlohmann::json report = nlohmann::json::parse(fitted.out);
    EXPECT_EQ(report.at("input_kind"), kind);
    EXPECT_EQ(report.at("signs"), "convex");
    // The Steiner point of a sphere is its centre; its radii are all R; its volume 4 pi R^3 / 3.
    const auto& steiner = report.at("steiner_point");
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(steiner.at(axis).get<double>(), center[axis], 1e-4) << kind;
    }
    EXPECT_NEAR(report.at("radii").at("min").get<double>(), 1.0, 5e-3) << kind;  // 0.1 voxel
    EXPECT_NEAR(report.at("radii").at("max").get<double>(), 1.0, 5e-3) << kind;
    EXPECT_NEAR(report.at("safe_offset").at("min").get<double>(), -1.0, 5e-3) << kind;
    EXPECT_NEAR(report.at("volume").get<double>() / (4.0 * d2vdb::kPi / 3.0), 1.0, 2e-3);
    volumes.push_back(report.at("volume").get<double>());
  }
  EXPECT_EQ(volumes[0], volumes[1]);  // the stored field answers as the level set's field did
  // Its offset by 0.5 is the sphere of radius 1.5.
  ASSERT_EQ(
      run("offset " + path("s.vdb.json") + " " + path("o.obj") + " --distance 0.5 --subdivisions 3")
          .exitCode,
      0);
  const d2vdb::TriangleMesh offset = d2vdb::readMesh(file("o.obj"));
  ASSERT_EQ(offset.vertexCount(), 642u);
  for (const Eigen::Vector3f& p : offset.positions) {
    EXPECT_NEAR((p.cast<double>() - center).norm(), 1.5, 5e-3);
  }
}

// A .vdb output gets each offset as a level set: the support-function offset's tessellation
// converted at the voxel size, or the level-set method's offset grid itself; both against the
// exact distance to the offset ellipsoid at the band voxels nearest the surface.
TEST_F(SupportCliTest, OffsetsAsLevelSets) {
  const std::string mesh = ellipsoidMesh(4);
  ASSERT_EQ(run("support " + mesh + " --degree 10 --out " + path("e.json")).exitCode, 0);
  const double d = 0.25;
  const CliResult bySupport = run("offset " + path("e.json") + " " + path("s.vdb") +
                                  " --distance 0.25 --subdivisions 5 --voxel-size 0.1 --json");
  ASSERT_EQ(bySupport.exitCode, 0) << bySupport.err;
  const nlohmann::json output = nlohmann::json::parse(bySupport.out).at("outputs").at(0);
  EXPECT_NEAR(output.at("voxel_size").get<double>(), 0.1, 1e-12);
  const CliResult byLevelSet = run("offset " + mesh + " " + path("l.vdb") +
                                   " --distance 0.25 --method levelset --voxel-size 0.1");
  ASSERT_EQ(byLevelSet.exitCode, 0) << byLevelSet.err;
  const d2vdb::test::Ellipsoid ellipsoid;
  // Worst |value - exact signed distance to the offset| over voxels within half a voxel of it.
  const auto worstError = [&](const std::string& name) {
    const openvdb::FloatGrid::Ptr grid = d2vdb::readLevelSet(file(name));
    EXPECT_NEAR(grid->voxelSize()[0], 0.1, 1e-12) << name;
    double worst = 0.0;
    std::size_t checked = 0;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
      if (std::abs(*it) > 0.05) continue;
      const openvdb::Vec3d w = grid->indexToWorld(it.getCoord());
      const double exact =
          d2vdb::test::signedDistanceToEllipsoid(ellipsoid, Eigen::Vector3d(w.x(), w.y(), w.z())) -
          d;
      worst = std::max(worst, std::abs(static_cast<double>(*it) - exact));
      ++checked;
    }
    EXPECT_GT(checked, 500u) << name;
    return worst;
  };
  const double supportError = worstError("s.vdb");
  const double levelSetError = worstError("l.vdb");
  std::printf(
      "offset 0.25 as a level set at voxel 0.1: max error %.3g (support), %.3g (level set)\n",
      supportError, levelSetError);
  EXPECT_LT(supportError, 2e-3);   // the fit at L = 10 and the tessellation's chords
  EXPECT_LT(levelSetError, 0.02);  // a fifth of a voxel
  // A patch's offsets are open: no signed level set.
  d2vdb::writeMesh(file("hyperboloid.obj"), d2vdb::test::hyperboloidPatch(32, 11, 0.5));
  const CliResult patch =
      run("offset " + path("hyperboloid.obj") + " " + path("p.vdb") + " --distance 0.1 --degree 8");
  EXPECT_EQ(patch.exitCode, 2);
  EXPECT_NE(patch.err.find("open surfaces"), std::string::npos) << patch.err;
  EXPECT_FALSE(exists("p.vdb"));
}

TEST_F(SupportCliTest, LevelSetMethodOffsetsTheMesh) {
  const CliResult result = run("offset " + ellipsoidMesh(3) + " " + path("ls.obj") +
                               " --distance 0.2 --method levelset --resolution 48 --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report.at("method"), "levelset");
  EXPECT_NEAR(report.at("voxel_size").get<double>(), 4.0 / 48.0, 1e-3);
  const d2vdb::TriangleMesh mesh = d2vdb::readMesh(file("ls.obj"));
  const d2vdb::test::Ellipsoid ellipsoid;
  // The level-set offset of a coarse mesh at a coarse voxel: within a voxel of the exact offset.
  for (std::size_t i = 0; i < mesh.positions.size(); i += 101) {
    const double distance =
        d2vdb::test::signedDistanceToEllipsoid(ellipsoid, mesh.positions[i].cast<double>());
    EXPECT_NEAR(distance, 0.2, 4.0 / 48.0) << i;
  }
}

// A torus (R = 2, r = 0.5: outer half convex, inner half saddle) as a grid mesh with exact
// normals: refused as a whole, split by --patches; the offsets of the patches lie on the offset
// torus (tube radius r + d); an offset outside the common safe range is refused.
TEST_F(SupportCliTest, PatchesSplitANonConvexTorus) {
  constexpr double kMajor = 2.0, kMinor = 0.5;
  d2vdb::TriangleMesh torus;
  const int around = 64, tube = 32;
  for (int i = 0; i < around; ++i) {
    const double u = 2.0 * d2vdb::kPi * i / around;
    for (int j = 0; j < tube; ++j) {
      const double v = 2.0 * d2vdb::kPi * j / tube;
      const Eigen::Vector3d n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
      const Eigen::Vector3d p =
          kMajor * Eigen::Vector3d(std::cos(u), std::sin(u), 0.0) + kMinor * n;
      torus.positions.push_back(p.cast<float>());
      torus.normals.push_back(n.cast<float>());
    }
  }
  const auto index = [&](int i, int j) {
    return static_cast<d2vdb::TriangleMesh::Index>((i % around) * tube + (j % tube));
  };
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < tube; ++j) {
      torus.triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      torus.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  }
  d2vdb::writeMesh(file("torus.obj"), torus);

  CliResult result = run("support " + path("torus.obj") + " --degree 12 --out " + path("t.json"));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("--patches"), std::string::npos) << result.err;
  EXPECT_FALSE(exists("t.json"));

  result = run("support " + path("torus.obj") + " --degree 12 --patches --out " + path("t.json") +
               " --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  ASSERT_EQ(report.at("patches").size(), 2u);
  EXPECT_EQ(report.at("patches")[0].at("signs"), "convex");
  EXPECT_EQ(report.at("patches")[1].at("signs"), "saddle");
  EXPECT_GT(report.at("triangles").at("parabolic").get<int>(), 0);
  EXPECT_EQ(report.at("triangles").at("uncovered"), report.at("triangles").at("parabolic"));
  // The common safe range lies inside the torus's own (-r, R - r).
  const double lo = report.at("safe_offset").at("min").get<double>();
  const double hi = report.at("safe_offset").at("max").get<double>();
  EXPECT_GE(lo, -kMinor - 1e-3);
  EXPECT_LT(lo, 0.0);
  EXPECT_NEAR(hi, kMajor - kMinor, 0.01);
  for (const std::string name : {"t_p0.json", "t_p1.json"}) {
    EXPECT_EQ(report.at("patches")[name == "t_p0.json" ? 0 : 1].at("output"), file(name).string());
    EXPECT_TRUE(exists(name)) << name;
  }

  result = run("offset " + path("torus.obj") + " " + path("o.obj") +
               " --distance 0.2 --degree 12 --patches --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const d2vdb::TriangleMesh offset = d2vdb::readMesh(file("o.obj"));
  ASSERT_GT(offset.vertexCount(), 1000u);
  double worst = 0.0;
  for (const Eigen::Vector3f& p : offset.positions) {
    const double tubeDistance = std::hypot(std::hypot(p.x(), p.y()) - kMajor, p.z());
    worst = std::max(worst, std::abs(tubeDistance - (kMinor + 0.2)));
  }
  EXPECT_LT(worst, 1e-3);

  result = run("offset " + path("torus.obj") + " " + path("far.obj") +
               " --distance 1.8 --degree 12 --patches");
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("every patch stays regular"), std::string::npos) << result.err;
  EXPECT_FALSE(exists("far.obj"));
}

TEST_F(SupportCliTest, BadInputExitsWithCodeTwoAndWritesNothing) {
  const std::string mesh = ellipsoidMesh(0);  // 12 vertices
  // Fewer samples than unknowns.
  CliResult result = run("support " + mesh + " --degree 4 --out " + path("a.json"));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("fewer than the 25 unknowns"), std::string::npos) << result.err;
  EXPECT_FALSE(exists("a.json"));
  // Degree beyond the limit.
  result = run("support " + mesh + " --degree 65 --out " + path("a.json"));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("not supported"), std::string::npos) << result.err;
  EXPECT_FALSE(exists("a.json"));
  // A point set with a zero normal.
  {
    std::ofstream ply(file("points.ply"));
    ply << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
           "end_header\n1 0 0 1 0 0\n0 1 0 0 0 0\n0 0 1 0 0 1\n";
  }
  result = run("support " + path("points.ply") + " --degree 0 --out " + path("p.json"));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("zero normal"), std::string::npos) << result.err;
  EXPECT_FALSE(exists("p.json"));
  // A NaN normal (rejected by the PLY reader with the line).
  {
    std::ofstream ply(file("nan.ply"));
    ply << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
           "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
           "end_header\n1 0 0 nan 0 0\n";
  }
  result = run("support " + path("nan.ply") + " --degree 0 --out " + path("n.json"));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_FALSE(exists("n.json"));
  // A non-convex closed mesh: the bundled bunny.
  result = run(std::string("support '") + D2VDB_SOURCE_DIR +
               "/volumes/bunny.obj' --degree 8 --out " + path("b.json"));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("not injective"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("--patches"), std::string::npos) << result.err;
  EXPECT_FALSE(exists("b.json"));
  // --patches needs triangles (a point set has no connectivity to split).
  result = run("support " + path("points.ply") + " --patches --out " + path("p.json"));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("connectivity"), std::string::npos) << result.err;
  EXPECT_FALSE(exists("p_p0.json"));
  result = run(std::string("offset '") + D2VDB_SOURCE_DIR + "/volumes/bunny.obj' " + path("b.obj") +
               " --distance 0.01 --degree 8");
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_FALSE(exists("b.obj"));
  // Offsets outside the safe range; a malformed support-function file.
  ASSERT_EQ(run("support " + ellipsoidMesh(3) + " --degree 8 --out " + path("e.json")).exitCode, 0);
  result =
      run("offset " + path("e.json") + " " + path("o.obj") + " --distance 0.1 --distance -0.7");
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("safe range"), std::string::npos) << result.err;
  EXPECT_FALSE(exists("o_d0.1.obj"));
  EXPECT_FALSE(exists("o_d-0.7.obj"));
  {
    std::ifstream in(file("e.json"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text.replace(text.find("\"degree\""), 0, "\"colour\": \"red\", ");
    std::ofstream(file("bad.json")) << text;
  }
  result = run("offset " + path("bad.json") + " " + path("o.obj") + " --distance 0.1");
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("colour"), std::string::npos) << result.err;
  EXPECT_FALSE(exists("o.obj"));
  result = run("info " + path("bad.json"));
  EXPECT_EQ(result.exitCode, 2);
}

}  // namespace
