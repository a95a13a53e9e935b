// End-to-end tests of `d2vdb smooth`: output mesh, curvature properties, JSON report, thread
// independence, and refusals (exit 2 for bad input, exit 1 for bad options, nothing written).
#include <gtest/gtest.h>

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

const char* kOctahedron =
    "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
    "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

class SmoothCliTest : public d2vdb::test::CliFixture {
 protected:
  static std::string bunny() { return std::string("'") + D2VDB_SOURCE_DIR + "/volumes/bunny.obj'"; }
};

TEST_F(SmoothCliTest, SmoothsTheBunnyWithCurvatures) {
  const CliResult result =
      run("smooth " + bunny() + " " + path("bunny.ply") + " --lod 1 --curvature --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  for (const char* key :
       {"input", "output", "source", "lod", "vertices", "faces", "degrees", "output_vertices",
        "output_triangles", "distance_to_source", "distance_to_mesh", "subdivided_faces",
        "curvature", "seconds", "diagonal"}) {
    EXPECT_TRUE(report.contains(key)) << key;
  }
  EXPECT_EQ(report["vertices"], 1839);
  EXPECT_EQ(report["faces"], 3674);
  EXPECT_EQ(report["output_triangles"], 3674 * 4);
  EXPECT_EQ(report["degrees"]["3"], 11);
  EXPECT_EQ(report["degrees"]["10"], 5);
  EXPECT_GT(report["subdivided_faces"].get<int>(), 0);
  EXPECT_LE(report["distance_to_source"]["max_relative"].get<double>(), 1.5e-3);
  // The Loop limit surface does not pass through the mesh's vertices: the smooth surface lies
  // farther from the input mesh than from its source (tests/manifold checks the figure itself).
  EXPECT_GT(report["distance_to_mesh"]["max"].get<double>(),
            report["distance_to_source"]["max"].get<double>());
  EXPECT_GE(report["distance_to_mesh"]["max"].get<double>(),
            report["distance_to_mesh"]["rms"].get<double>());
  EXPECT_GT(report["curvature"]["k1"]["max"].get<double>(),
            report["curvature"]["k2"]["max"].get<double>());
  const std::string file = readWholeFile(scratch_ / "bunny.ply");
  EXPECT_NE(file.find("property float k1\nproperty float k2\nproperty uchar red\n"),
            std::string::npos);
  const d2vdb::TriangleMesh mesh = d2vdb::readMesh(scratch_ / "bunny.ply");
  EXPECT_EQ(mesh.triangleCount(), 3674u * 4u);
  EXPECT_TRUE(mesh.hasNormals());
  const d2vdb::MeshReport check = d2vdb::validateMesh(mesh);
  EXPECT_TRUE(check.closed && check.manifold && check.oriented) << check.problems();
  EXPECT_EQ(check.eulerCharacteristic, 2);
  // The same bytes with one and with two threads.
  ASSERT_EQ(run("smooth " + bunny() + " " + path("one.ply") + " --lod 1 --curvature -q --threads 1")
                .exitCode,
            0);
  ASSERT_EQ(run("smooth " + bunny() + " " + path("two.ply") + " --lod 1 --curvature -q --threads 2")
                .exitCode,
            0);
  EXPECT_EQ(readWholeFile(scratch_ / "one.ply"), readWholeFile(scratch_ / "two.ply"));
}

TEST_F(SmoothCliTest, PnSourceUsesTheFileNormals) {
  const std::string withNormals =
      "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
      "vn 1 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\nvn 0 0 1\nvn 0 0 -1\n"
      "f 1//1 3//3 5//5\nf 3//3 2//2 5//5\nf 2//2 4//4 5//5\nf 4//4 1//1 5//5\n"
      "f 3//3 1//1 6//6\nf 2//2 3//3 6//6\nf 4//4 2//2 6//6\nf 1//1 4//4 6//6\n";
  write("octa.obj", withNormals);
  const CliResult result =
      run("smooth " + path("octa.obj") + " " + path("octa.stl") + " --source pn --lod 3 --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["source"], "pn");
  EXPECT_EQ(report["normals"], "file");
  EXPECT_EQ(report["output_triangles"], 8 * 64);
  EXPECT_FALSE(report.contains("subdivided_faces"));
}

TEST_F(SmoothCliTest, RefusesMeshesThatAreNotClosedManifolds) {
  // An octahedron with a face missing: exit 2, the boundary edges named, nothing written and an
  // existing output left as it was.
  std::string open = kOctahedron;
  open = open.substr(0, open.rfind("f "));
  write("open.obj", open);
  write("out.ply", "keep me");
  const CliResult result = run("smooth " + path("open.obj") + " " + path("out.ply"));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.err.find("boundary edges"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("(0, 3), (0, 5), (3, 5)"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("open.obj"), std::string::npos) << result.err;
  EXPECT_EQ(readWholeFile(scratch_ / "out.ply"), "keep me");
  // Two triangles wound alike across an edge.
  std::string flipped = kOctahedron;
  flipped.replace(flipped.find("f 1 3 5"), 7, "f 1 5 3");
  write("flipped.obj", flipped);
  const CliResult bad = run("smooth " + path("flipped.obj") + " " + path("flipped.ply"));
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("inconsistently oriented"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(scratch_ / "flipped.ply"));
}

TEST_F(SmoothCliTest, RefusesBadFilesAndOptions) {
  write("octa.obj", kOctahedron);
  write("broken.obj", "v 1 0 0\nv 0 1 0\nv 0 0 nan\nf 1 2 3\n");
  const CliResult broken = run("smooth " + path("broken.obj") + " " + path("a.ply"));
  EXPECT_EQ(broken.exitCode, 2);
  EXPECT_NE(broken.err.find("broken.obj"), std::string::npos) << broken.err;
  const CliResult missing = run("smooth " + path("nothing.obj") + " " + path("a.ply"));
  EXPECT_EQ(missing.exitCode, 2);
  // Curvature needs PLY (an output named for another format: bad input); level of detail and
  // source are checked: usage errors.
  const CliResult obj = run("smooth " + path("octa.obj") + " " + path("a.obj") + " --curvature");
  EXPECT_EQ(obj.exitCode, 2);
  EXPECT_NE(obj.err.find("--curvature"), std::string::npos) << obj.err;
  EXPECT_EQ(run("smooth " + path("octa.obj") + " " + path("a.ply") + " --lod 11").exitCode, 1);
  EXPECT_EQ(run("smooth " + path("octa.obj") + " " + path("a.ply") + " --source catmull").exitCode,
            1);
  const CliResult unknown = run("smooth " + path("octa.obj") + " " + path("a.off"));
  EXPECT_EQ(unknown.exitCode, 2);
  // Too many triangles: refused before anything is allocated.
  const CliResult huge = run("smooth " + bunny() + " " + path("huge.ply") + " --lod 10");
  EXPECT_EQ(huge.exitCode, 2);
  EXPECT_NE(huge.err.find("choose a lower level"), std::string::npos) << huge.err;
  for (const char* name : {"a.ply", "a.obj", "a.off", "huge.ply"}) {
    EXPECT_FALSE(fs::exists(scratch_ / name)) << name;
  }
}

TEST_F(SmoothCliTest, FieldOfTheSmoothSurface) {
  write("octa.obj", kOctahedron);
  const CliResult result = run("field " + path("octa.obj") + " " + path("octa.vdb") +
                               " --smooth --resolution 24 --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["input_kind"], "mesh");
  EXPECT_EQ(report["smooth"]["source"], "loop");
  EXPECT_EQ(report["smooth"]["subdivided_faces"], 8);
  EXPECT_NE(report["estimator"].get<std::string>().find("smooth surface"), std::string::npos);
  EXPECT_GT(report["active_voxels"].get<long>(), 1000);
  // The written field answers queries like any other.
  const CliResult query = run("query " + path("octa.vdb") + " 0 0 0.7 --json");
  ASSERT_EQ(query.exitCode, 0) << query.err;
  const auto answer = nlohmann::json::parse(query.out);
  // Above the top vertex, outside the surface (the Loop limit surface of an octahedron lies well
  // inside it): a positive distance along z to a convex footpoint on the z axis.
  EXPECT_GT(answer["k1"].get<double>(), 0.0);
  EXPECT_NEAR(answer["distance"].get<double>(), 0.7 - answer["footpoint"][2].get<double>(), 1e-6);
  // PN source; refusals: not a mesh, not a closed manifold.
  EXPECT_EQ(
      run("field " + path("octa.obj") + " " + path("pn.vdb") + " --smooth pn --resolution 16 -q")
          .exitCode,
      0);
  write("line.json",
        R"({"type": "polyline", "version": 1, "dimension": 2, "points": [[0, 0], [1, 0]]})");
  const CliResult curve = run("field " + path("line.json") + " " + path("c.vdb") + " --smooth");
  EXPECT_EQ(curve.exitCode, 2);
  EXPECT_NE(curve.err.find("--smooth"), std::string::npos) << curve.err;
  std::string open = kOctahedron;
  write("open.obj", open.substr(0, open.rfind("f ")));
  const CliResult bad = run("field " + path("open.obj") + " " + path("o.vdb") + " --smooth");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("boundary edges"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(scratch_ / "c.vdb"));
  EXPECT_FALSE(fs::exists(scratch_ / "o.vdb"));
}

}  // namespace
