// Reading and writing OBJ, PLY and STL: exact round trips, and hand-written files with known
// contents.
#include "d2vdb/mesh/MeshIO.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <sstream>

#include "d2vdb/mesh/MeshValidation.h"
#include "d2vdb/mesh/VertexNormals.h"
#include "d2vdb/mesh/detail/ObjFormat.h"
#include "d2vdb/mesh/detail/PlyFormat.h"
#include "d2vdb/mesh/detail/StlFormat.h"
#include "mesh/MeshTestSupport.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::MeshFormat;
using d2vdb::MeshWriteOptions;
using d2vdb::TriangleMesh;
using d2vdb::test::ByteWriter;
using d2vdb::test::expectIdentical;
using d2vdb::test::makeMesh;
using d2vdb::test::readWholeFile;

class MeshIOTest : public d2vdb::test::ScratchDirectoryTest {};

/// A closed mesh whose coordinates are hard to print exactly (thirds, tiny, huge, subnormal,
/// negative zero, integers beyond float precision), with every vertex in first-use order so that
/// even STL's welding gives the same numbering back.
TriangleMesh awkwardMesh() {
  TriangleMesh mesh = d2vdb::test::tetrahedron();
  mesh.positions[0] = {-0.0f, 1.0f / 3.0f, 1e-7f};
  mesh.positions[1] = {123456.789f, -2.0f / 3.0f, 16777216.0f};
  mesh.positions[2] = {0.1f, std::numeric_limits<float>::denorm_min(),
                       std::numeric_limits<float>::min()};
  mesh.positions[3] = {-3.4028235e38f, 0.3f, 2.5e-12f};
  mesh.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  return mesh;
}

TriangleMesh withNormals(TriangleMesh mesh) {
  d2vdb::computeVertexNormals(mesh);
  return mesh;
}

TEST_F(MeshIOTest, FormatFromExtensionIgnoresCase) {
  EXPECT_EQ(d2vdb::meshFormatFromPath("a/b/Bunny.OBJ"), MeshFormat::Obj);
  EXPECT_EQ(d2vdb::meshFormatFromPath("x.Ply"), MeshFormat::Ply);
  EXPECT_EQ(d2vdb::meshFormatFromPath("x.stl"), MeshFormat::Stl);
  d2vdb::test::expectInputError([] { d2vdb::meshFormatFromPath("model.off"); },
                                {"model.off", "'.off'", ".obj", ".ply", ".stl"});
  d2vdb::test::expectInputError([] { d2vdb::meshFormatFromPath("model"); },
                                {"no extension", ".obj"});
}

TEST_F(MeshIOTest, ObjRoundTripIsExact) {
  for (const TriangleMesh& mesh : {awkwardMesh(), withNormals(awkwardMesh())}) {
    const fs::path path = scratch_ / "mesh.obj";
    d2vdb::writeMesh(path, mesh);
    expectIdentical(d2vdb::readMesh(path), mesh);
  }
  // The OBJ with normals uses the f a//a form.
  d2vdb::writeMesh(scratch_ / "n.obj", withNormals(awkwardMesh()));
  EXPECT_NE(readWholeFile(scratch_ / "n.obj").find("\nf 1//1 2//2 3//3\n"), std::string::npos);
}

TEST_F(MeshIOTest, PlyRoundTripIsExactInEveryEncoding) {
  const std::vector<std::pair<MeshWriteOptions, std::string>> variants = {
      {{false, false}, "format ascii 1.0\n"},
      {{true, false}, "format binary_little_endian 1.0\n"},
      {{true, true}, "format binary_big_endian 1.0\n"}};
  for (const auto& [options, formatLine] : variants) {
    for (const TriangleMesh& mesh : {awkwardMesh(), withNormals(awkwardMesh())}) {
      SCOPED_TRACE(formatLine + (mesh.hasNormals() ? " with normals" : ""));
      const fs::path path = scratch_ / "mesh.ply";
      d2vdb::writeMesh(path, mesh, options);
      EXPECT_NE(readWholeFile(path).find(formatLine), std::string::npos);
      expectIdentical(d2vdb::readMesh(path), mesh);
    }
  }
}

TEST_F(MeshIOTest, BinaryPlyUsesTheDeclaredByteOrder) {
  const TriangleMesh mesh = makeMesh({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 1, 2}});
  for (const bool bigEndian : {false, true}) {
    std::ostringstream out;
    d2vdb::detail::writePly(out, mesh,
                            bigEndian ? d2vdb::detail::PlyEncoding::BinaryBigEndian
                                      : d2vdb::detail::PlyEncoding::BinaryLittleEndian);
    const std::string bytes = out.str();
    const std::size_t body = bytes.find("end_header\n") + 11;
    // 1.0f is 3F 80 00 00; the face is uchar 3 then three uint32 indices.
    const std::string one =
        bigEndian ? std::string("\x3F\x80\x00\x00", 4) : std::string("\x00\x00\x80\x3F", 4);
    EXPECT_EQ(bytes.substr(body, 4), one);
    ASSERT_EQ(bytes.size(), body + 9 * 4 + 1 + 3 * 4);
    EXPECT_EQ(bytes[body + 36], '\x03');
    const std::string two =
        bigEndian ? std::string("\x00\x00\x00\x02", 4) : std::string("\x02\x00\x00\x00", 4);
    EXPECT_EQ(bytes.substr(body + 37 + 8, 4), two);
  }
}

TEST_F(MeshIOTest, StlRoundTripIsExactUpToWelding) {
  for (const bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    const fs::path path = scratch_ / "mesh.stl";
    d2vdb::writeMesh(path, withNormals(awkwardMesh()), {binary, false});
    // STL keeps no vertex normals; vertices come back in first-use order, which awkwardMesh keeps.
    expectIdentical(d2vdb::readMesh(path), awkwardMesh());
  }
}

TEST_F(MeshIOTest, StlWeldsSharedCornersOfAnyMesh) {
  // A cube whose vertex numbering differs from first use, plus an unused vertex: the corners
  // come back welded (8 vertices, closed), each triangle with the same corner positions.
  TriangleMesh mesh = d2vdb::test::cube(Eigen::Vector3f(-0.5f, 2.0f, 10.0f));
  std::reverse(mesh.positions.begin(), mesh.positions.end());
  for (TriangleMesh::Triangle& triangle : mesh.triangles) {
    for (TriangleMesh::Index& index : triangle) index = 7 - index;
  }
  mesh.positions.emplace_back(9.0f, 9.0f, 9.0f);
  for (const bool binary : {true, false}) {
    const fs::path path = scratch_ / "cube.stl";
    d2vdb::writeMesh(path, mesh, {binary, false});
    const TriangleMesh read = d2vdb::readMesh(path);
    EXPECT_EQ(read.vertexCount(), 8u);
    ASSERT_EQ(read.triangleCount(), mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(read.positions[read.triangles[t][k]], mesh.positions[mesh.triangles[t][k]]);
      }
    }
    EXPECT_TRUE(d2vdb::validateMesh(read).closed);
  }
}

TEST_F(MeshIOTest, BinaryStlLayoutAndFacetNormals) {
  const TriangleMesh mesh = makeMesh({{0, 0, 0}, {2, 0, 0}, {0, 3, 0}}, {{0, 1, 2}});
  std::ostringstream out;
  d2vdb::detail::writeStl(out, mesh, d2vdb::detail::StlEncoding::Binary);
  const std::string bytes = out.str();
  ASSERT_EQ(bytes.size(), 84u + 50u);
  EXPECT_NE(bytes.substr(0, 5), "solid");
  EXPECT_EQ(bytes.substr(80, 4), std::string("\x01\x00\x00\x00", 4));
  // Facet normal (0, 0, 1): 0.0f, 0.0f, 1.0f in little-endian order.
  EXPECT_EQ(bytes.substr(84, 12), std::string("\0\0\0\0\0\0\0\0\x00\x00\x80\x3F", 12));

  std::ostringstream text;
  d2vdb::detail::writeStl(text, mesh, d2vdb::detail::StlEncoding::Ascii);
  EXPECT_NE(text.str().find("facet normal 0 0 1\n"), std::string::npos) << text.str();
  EXPECT_EQ(text.str().rfind("solid", 0), 0u);
}

TEST_F(MeshIOTest, BinaryStlBeginningWithSolidIsReadAsBinary) {
  ByteWriter file;
  std::string header = "solid this header lies: the file is binary";
  header.resize(80, ' ');
  file.text(header).u32(2);
  const float corners[2][3][3] = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                  {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}}};
  for (const auto& facet : corners) {
    file.f32(0).f32(0).f32(1);
    for (const auto& corner : facet) file.f32(corner[0]).f32(corner[1]).f32(corner[2]);
    file.u16(0);
  }
  EXPECT_EQ(d2vdb::detail::detectStlEncoding(file.bytes()), d2vdb::detail::StlEncoding::Binary);
  const TriangleMesh mesh = d2vdb::readMesh(write("liar.stl", file.bytes()));
  ASSERT_EQ(mesh.vertexCount(), 4u);
  EXPECT_EQ(mesh.positions[0], Eigen::Vector3f(0, 0, 0));
  EXPECT_EQ(mesh.positions[1], Eigen::Vector3f(1, 0, 0));
  EXPECT_EQ(mesh.positions[2], Eigen::Vector3f(0, 1, 0));
  EXPECT_EQ(mesh.positions[3], Eigen::Vector3f(1, 1, 0));
  EXPECT_EQ(mesh.triangles, (std::vector<TriangleMesh::Triangle>{{0, 1, 2}, {1, 3, 2}}));
  EXPECT_TRUE(mesh.normals.empty());
}

TEST_F(MeshIOTest, AsciiStlWithSeveralSolidsAndMixedCase) {
  const std::string text =
      "solid first part\n"
      "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n"
      "      vertex 0 1 0\n    endloop\n  endfacet\nendsolid first part\n"
      "SOLID second\r\n FACET NORMAL 0 0 -1E0\r\n OUTER LOOP\r\n VERTEX 1 0 0\r\n"
      " VERTEX -0 1 0\r\n VERTEX 1e0 1 0\r\n ENDLOOP\r\n ENDFACET\r\nENDSOLID second\r\n";
  const TriangleMesh mesh = d2vdb::detail::parseStl(text, "two.stl");
  ASSERT_EQ(mesh.vertexCount(), 4u);  // -0 welds with 0; 1e0 with 1
  EXPECT_EQ(mesh.triangles, (std::vector<TriangleMesh::Triangle>{{0, 1, 2}, {1, 2, 3}}));
  EXPECT_EQ(mesh.positions[3], Eigen::Vector3f(1, 1, 0));
}

TEST_F(MeshIOTest, ObjPolygonsAreFanTriangulated) {
  const TriangleMesh mesh = d2vdb::readMesh(
      write("polygons.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 3 0 0\nv 3 1 0\nv 2.5 2 0\nv 2 1 0\n"
            "f 1 2 3 4\n"
            "f 5 6 7 8 9\n"));
  EXPECT_EQ(mesh.vertexCount(), 9u);
  EXPECT_EQ(mesh.triangles, (std::vector<TriangleMesh::Triangle>{
                                {0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}, {4, 7, 8}}));
  EXPECT_TRUE(mesh.normals.empty());
}

TEST_F(MeshIOTest, ObjCornerFormsNegativeIndicesAndIgnoredStatements) {
  const std::string text =
      "# comment line\r\n"
      "mtllib scene.mtl\r\n"
      "o thing\r\n"
      "g group\r\n"
      "\r\n"
      "v 0 0 0 1.0\r\n"             // optional w
      "v 1 0 0 0.5 0.25 0.125\r\n"  // w... or vertex colours
      "v\t0\t1\t0\r\n"
      "vt 0 0\r\nvt 1 0\r\nvt 0 1\r\n"
      "vn 0 0 1\r\n"
      "usemtl red\r\n"
      "s off\r\n"
      "f 1/1/1 2/2/1 3/3/1  # trailing comment\r\n"
      "v 1 1 0\r\n"
      "f -3//-1 -1//-1 -2//-1\r\n"
      "f 2/2 4/3 3/1\r\n"
      "l 1 2\r\n";
  const TriangleMesh mesh = d2vdb::detail::parseObj(text, "corners.obj");
  ASSERT_EQ(mesh.vertexCount(), 4u);
  EXPECT_EQ(mesh.positions[1], Eigen::Vector3f(1, 0, 0));
  EXPECT_EQ(mesh.positions[2], Eigen::Vector3f(0, 1, 0));
  EXPECT_EQ(mesh.triangles, (std::vector<TriangleMesh::Triangle>{{0, 1, 2}, {1, 3, 2}, {1, 3, 2}}));
  // The last face names no normals, so per-vertex normals are dropped.
  EXPECT_TRUE(mesh.normals.empty());
}

TEST_F(MeshIOTest, ObjNormalsFollowTheFaceCorners) {
  // Normals listed in a different order from the vertices, with a duplicate normal value.
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
      "vn 0 0 -1\nvn 0 0 1\nvn 0 0 1\n"
      "f 1//2 2//2 3//3\nf 2//3 4//2 3//2\n";
  const TriangleMesh mesh = d2vdb::detail::parseObj(text, "normals.obj");
  ASSERT_TRUE(mesh.hasNormals());
  for (const Eigen::Vector3f& normal : mesh.normals) EXPECT_EQ(normal, Eigen::Vector3f(0, 0, 1));

  // Vertex 2 named with two different normals: normals are dropped, the geometry is kept.
  const TriangleMesh conflicting = d2vdb::detail::parseObj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 1 0 0\nf 1//1 2//1 3//1\nf 2//2 4//2 "
      "3//2\n",
      "conflict.obj");
  EXPECT_TRUE(conflicting.normals.empty());
  EXPECT_EQ(conflicting.triangleCount(), 2u);
}

TEST_F(MeshIOTest, ObjNormalsOfFacesBeforeTheirVertices) {
  // OBJ lets a face name vertices defined further down; their normals are checked the same way.
  const TriangleMesh mesh = d2vdb::detail::parseObj(
      "vn 0 0 1\nf 1//1 2//1 3//1\nf 2//1 4//1 3//1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n",
      "forward.obj");
  ASSERT_TRUE(mesh.hasNormals());
  EXPECT_EQ(mesh.normals.size(), 4u);
  for (const Eigen::Vector3f& normal : mesh.normals) EXPECT_EQ(normal, Eigen::Vector3f(0, 0, 1));

  // Vertex 2 is defined between its two faces, which give it different normals.
  const TriangleMesh conflicting = d2vdb::detail::parseObj(
      "vn 0 0 1\nvn 1 0 0\nv 0 0 0\nf 1//1 2//1 3//1\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
      "f 2//2 4//2 3//2\n",
      "forward_conflict.obj");
  EXPECT_TRUE(conflicting.normals.empty());
  EXPECT_EQ(conflicting.triangleCount(), 2u);
}

TEST_F(MeshIOTest, ByteOrderMarkIsSkipped) {
  const TriangleMesh obj =
      d2vdb::detail::parseObj("\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bom.obj");
  EXPECT_EQ(obj.triangles, (std::vector<TriangleMesh::Triangle>{{0, 1, 2}}));
  const TriangleMesh stl = d2vdb::detail::parseStl(
      "\xEF\xBB\xBFsolid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n",
      "bom.stl");
  EXPECT_EQ(stl.vertexCount(), 3u);
}

TEST_F(MeshIOTest, ObjFacesMayReferToLaterVertices) {
  const TriangleMesh mesh =
      d2vdb::detail::parseObj("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "late.obj");
  EXPECT_EQ(mesh.triangles, (std::vector<TriangleMesh::Triangle>{{0, 1, 2}}));
}

TEST_F(MeshIOTest, AsciiPlyWithExtraPropertiesAndElements) {
  const std::string text =
      "ply\n"
      "format ascii 1.0\n"
      "comment made by hand\n"
      "obj_info nothing to see\n"
      "element vertex 4\n"
      "property uchar red\n"
      "property float32 x\n"
      "property double y\n"
      "property int z\n"
      "property list uint8 int32 neighbours\n"
      "property float confidence\n"
      "element face 2\n"
      "property uchar flags\n"
      "property list uchar uint vertex_index\n"
      "property list int float texcoord\n"
      "element nothing 1000000000000\n"  // records without properties hold no data
      "element edge 1\n"
      "property int vertex1\n"
      "property int16 vertex2\n"
      "end_header\n"
      "255 0 0 0 2 1 2 0.5\n"
      "0 1.5 0 -3 0 nan\n"
      "7 1.5 2.25 -3 3 0 1 3 1e-3\n"
      "9 0 2.25 7 1 2 -4.5\n"
      "3 4 0 1 2 3 6 0 0 1 0 1 1\n"
      "0 3 0 2 3 0\n"
      "0 1\n"
      "\n";
  const TriangleMesh mesh = d2vdb::detail::parsePly(text, "extra.ply");
  ASSERT_EQ(mesh.vertexCount(), 4u);
  EXPECT_EQ(mesh.positions[0], Eigen::Vector3f(0, 0, 0));
  EXPECT_EQ(mesh.positions[1], Eigen::Vector3f(1.5f, 0, -3));
  EXPECT_EQ(mesh.positions[2], Eigen::Vector3f(1.5f, 2.25f, -3));
  EXPECT_EQ(mesh.positions[3], Eigen::Vector3f(0, 2.25f, 7));
  EXPECT_EQ(mesh.triangles, (std::vector<TriangleMesh::Triangle>{{0, 1, 2}, {0, 2, 3}, {0, 2, 3}}));
  EXPECT_TRUE(mesh.normals.empty());
}

/// The binary twin of the ASCII file above, built byte by byte.
std::string binaryPlyWithExtras(bool bigEndian) {
  ByteWriter file(bigEndian);
  file.text(std::string("ply\nformat ") +
            (bigEndian ? "binary_big_endian" : "binary_little_endian") +
            " 1.0\n"
            "comment binary with extras\n"
            "element vertex 3\n"
            "property char tag\n"
            "property float64 x\n"
            "property float y\n"
            "property short z\n"
            "property list ushort uint nb\n"
            "property float nx\nproperty float ny\nproperty float nz\n"
            "element material 2\n"
            "property uint id\n"
            "property list uchar double weights\n"
            "element face 1\n"
            "property list int int vertex_indices\n"
            "property ushort flags\n"
            "end_header\n");
  const auto vertex = [&](std::int8_t tag, double x, float y, std::int16_t z,
                          std::vector<std::uint32_t> nb, float nz) {
    file.i8(tag).f64(x).f32(y).i16(z).u16(static_cast<std::uint16_t>(nb.size()));
    for (const std::uint32_t n : nb) file.u32(n);
    file.f32(0).f32(0).f32(nz);
  };
  vertex(-1, 0.25, -1.5f, 3, {1, 2}, 1.0f);
  vertex(2, -8.0, 0.0f, -300, {}, -1.0f);
  vertex(3, 1e10, 2.5f, 0, {7}, 0.5f);
  file.u32(11).u8(2).f64(0.5).f64(-0.5);
  file.u32(12).u8(0);
  file.i32(3).i32(2).i32(0).i32(1).u16(0xBEEF);
  return file.bytes();
}

TEST_F(MeshIOTest, BinaryPlyWithExtraPropertiesAndElements) {
  for (const bool bigEndian : {false, true}) {
    SCOPED_TRACE(bigEndian ? "big endian" : "little endian");
    const TriangleMesh mesh = d2vdb::readMesh(write("extra.ply", binaryPlyWithExtras(bigEndian)));
    ASSERT_EQ(mesh.vertexCount(), 3u);
    EXPECT_EQ(mesh.positions[0], Eigen::Vector3f(0.25f, -1.5f, 3.0f));
    EXPECT_EQ(mesh.positions[1], Eigen::Vector3f(-8.0f, 0.0f, -300.0f));
    EXPECT_EQ(mesh.positions[2], Eigen::Vector3f(1e10f, 2.5f, 0.0f));
    EXPECT_EQ(mesh.triangles, (std::vector<TriangleMesh::Triangle>{{2, 0, 1}}));
    ASSERT_TRUE(mesh.hasNormals());
    EXPECT_EQ(mesh.normals[1], Eigen::Vector3f(0, 0, -1));
    EXPECT_EQ(mesh.normals[2], Eigen::Vector3f(0, 0, 0.5f));
  }
}

TEST_F(MeshIOTest, StreamFunctionsMatchFileFunctions) {
  const TriangleMesh mesh = withNormals(awkwardMesh());
  std::stringstream obj;
  d2vdb::detail::writeObj(obj, mesh);
  expectIdentical(d2vdb::detail::readObj(obj, "stream.obj"), mesh);
  std::stringstream ply;
  d2vdb::detail::writePly(ply, mesh, d2vdb::detail::PlyEncoding::BinaryBigEndian);
  expectIdentical(d2vdb::detail::readPly(ply, "stream.ply"), mesh);
  std::stringstream stl;
  d2vdb::detail::writeStl(stl, mesh, d2vdb::detail::StlEncoding::Ascii);
  expectIdentical(d2vdb::detail::readStl(stl, "stream.stl"), awkwardMesh());
}

TEST_F(MeshIOTest, LargeMeshRoundTripsThroughEveryFormat) {
  const TriangleMesh mesh = d2vdb::test::torus(300, 200);  // 120000 triangles
  for (const char* name : {"big.obj", "big.ply", "big.stl"}) {
    SCOPED_TRACE(name);
    const fs::path path = scratch_ / name;
    d2vdb::writeMesh(path, mesh);
    const TriangleMesh read = d2vdb::readMesh(path);
    if (fs::path(name).extension() != ".stl") {
      expectIdentical(read, mesh);
      continue;
    }
    // STL numbers the welded vertices by first use: same count, same corners per triangle.
    ASSERT_EQ(read.vertexCount(), mesh.vertexCount());
    ASSERT_EQ(read.triangleCount(), mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      for (std::size_t k = 0; k < 3; ++k) {
        ASSERT_EQ(read.positions[read.triangles[t][k]], mesh.positions[mesh.triangles[t][k]]);
      }
    }
  }
}

TEST_F(MeshIOTest, ReadMeshReportsMissingAndUnreadableFiles) {
  const fs::path missing = scratch_ / "missing.obj";
  d2vdb::test::expectInputError([&] { d2vdb::readMesh(missing); },
                                {missing.string(), "no such file"});
  fs::create_directories(scratch_ / "folder.ply");
  d2vdb::test::expectInputError([&] { d2vdb::readMesh(scratch_ / "folder.ply"); },
                                {"folder.ply", "directory"});
  d2vdb::test::expectInputError([&] { d2vdb::readMesh(write("mesh.3ds", "x")); },
                                {"mesh.3ds", "'.3ds'"});
}

TEST_F(MeshIOTest, FailedWriteLeavesExistingFileIntact) {
  const fs::path target = write("existing.obj", "precious contents");
  TriangleMesh broken = awkwardMesh();
  broken.triangles.push_back({0, 1, 9});
  d2vdb::test::expectInputError([&] { d2vdb::writeMesh(target, broken); },
                                {"triangle 4", "vertex 9"});
  TriangleMesh notFinite = awkwardMesh();
  notFinite.positions[2].y() = std::numeric_limits<float>::quiet_NaN();
  d2vdb::test::expectInputError([&] { d2vdb::writeMesh(target, notFinite); },
                                {"vertex 2", "non-finite"});
  d2vdb::test::expectInputError([&] { d2vdb::writeMesh(target, TriangleMesh{}); }, {"no vertices"});
  d2vdb::test::expectInputError(
      [&] {
        d2vdb::writeMesh(scratch_ / "points.stl", makeMesh({{0, 0, 0}}, {}));
      },
      {"no triangles"});
  EXPECT_THROW(d2vdb::writeMesh(scratch_ / "no" / "dir" / "x.obj", awkwardMesh()),
               d2vdb::RuntimeFailure);
  EXPECT_EQ(readWholeFile(target), "precious contents");
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(scratch_)) {
    left.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(left, std::vector<std::string>{"existing.obj"});
}

TEST_F(MeshIOTest, WriteReplacesExistingFile) {
  const fs::path target = write("mesh.ply", "old contents");
  d2vdb::writeMesh(target, awkwardMesh(), {false, false});
  expectIdentical(d2vdb::readMesh(target), awkwardMesh());
}

}  // namespace
