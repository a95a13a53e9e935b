// Per-vertex scalars and colours in PLY (ascii, binary) and OBJ files: what the header and body
// hold byte for byte, that the readers still read the geometry back, and bad attribute lists.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/MeshIO.h"
#include "mesh/MeshTestSupport.h"

namespace d2vdb {
namespace {

namespace fs = std::filesystem;

class VertexAttributesTest : public test::ScratchDirectoryTest {};

VertexAttributes attributesFor(const TriangleMesh& mesh) {
  VertexAttributes attributes;
  attributes.scalarName = "distance";
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    attributes.scalars.push_back(0.25f * static_cast<float>(v) - 0.5f);
    attributes.colors.push_back({static_cast<std::uint8_t>(10 * v), 128, 255});
  }
  return attributes;
}

TEST_F(VertexAttributesTest, AsciiPlyHoldsTheScalarAndColorsAfterThePosition) {
  const TriangleMesh mesh = test::tetrahedron();
  const fs::path path = scratch_ / "a.ply";
  MeshWriteOptions options;
  options.binary = false;
  writeMesh(path, mesh, attributesFor(mesh), options);
  const std::string text = test::readWholeFile(path);
  EXPECT_NE(text.find("property float z\nproperty float distance\nproperty uchar red\n"
                      "property uchar green\nproperty uchar blue\nelement face 4"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("\n1 0 0 -0.25 10 128 255\n"), std::string::npos) << text;
  const TriangleMesh back = readMesh(path);
  EXPECT_EQ(back.positions, mesh.positions);
  EXPECT_EQ(back.triangles, mesh.triangles);
}

TEST_F(VertexAttributesTest, FurtherNamedScalarsFollowTheScalarInPly) {
  const TriangleMesh mesh = test::tetrahedron();
  VertexAttributes attributes = attributesFor(mesh);
  attributes.moreScalars.push_back({"k1", {1.5f, -2.0f, 0.0f, 3.0f}});
  attributes.moreScalars.push_back({"k2", {-1.0f, 0.5f, 2.0f, 1e-7f}});
  MeshWriteOptions options;
  options.binary = false;
  const fs::path path = scratch_ / "more.ply";
  writeMesh(path, mesh, attributes, options);
  const std::string text = test::readWholeFile(path);
  EXPECT_NE(text.find("property float distance\nproperty float k1\nproperty float k2\n"
                      "property uchar red\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("\n1 0 0 -0.25 -2 0.5 10 128 255\n"), std::string::npos) << text;
  EXPECT_EQ(readMesh(path).positions, mesh.positions);
  writeMesh(scratch_ / "more_binary.ply", mesh, attributes);
  EXPECT_EQ(readMesh(scratch_ / "more_binary.ply").positions, mesh.positions);
  // Names: distinct, plain identifiers; values: one finite per vertex. Nothing is written.
  for (const auto& [name, values] :
       std::vector<std::pair<std::string, std::vector<float>>>{{"distance", {0, 0, 0, 0}},
                                                               {"red", {0, 0, 0, 0}},
                                                               {"k 1", {0, 0, 0, 0}},
                                                               {"k3", {0, 0, 0}},
                                                               {"k3", {0, 0, NAN, 0}}}) {
    VertexAttributes bad = attributesFor(mesh);
    bad.moreScalars.push_back({name, values});
    EXPECT_THROW(writeMesh(scratch_ / "bad.ply", mesh, bad), InputError) << name;
  }
  EXPECT_FALSE(fs::exists(scratch_ / "bad.ply"));
}

TEST_F(VertexAttributesTest, BinaryPlyRecordsHaveTheDeclaredLayout) {
  const TriangleMesh mesh = test::tetrahedron();
  const fs::path path = scratch_ / "b.ply";
  writeMesh(path, mesh, attributesFor(mesh));
  const std::string bytes = test::readWholeFile(path);
  const std::size_t body = bytes.find("end_header\n") + std::strlen("end_header\n");
  // Vertex 2: x y z distance (4 floats), then 3 colour bytes: 19 bytes per vertex.
  const std::size_t record = body + 2 * 19;
  float values[4];
  std::memcpy(values, bytes.data() + record, sizeof(values));
  EXPECT_EQ(values[1], 1.0f);
  EXPECT_EQ(values[3], 0.0f);
  EXPECT_EQ(static_cast<unsigned char>(bytes[record + 16]), 20u);
  EXPECT_EQ(static_cast<unsigned char>(bytes[record + 18]), 255u);
  EXPECT_EQ(readMesh(path).positions, mesh.positions);
}

TEST_F(VertexAttributesTest, ObjGetsVertexColorsOnly) {
  const TriangleMesh mesh = test::tetrahedron();
  const fs::path path = scratch_ / "c.obj";
  writeMesh(path, mesh, attributesFor(mesh));
  const std::string text = test::readWholeFile(path);
  EXPECT_NE(text.find("\nv 0 0 1 0.11764706 0.5019608 1\n"), std::string::npos) << text;
  EXPECT_EQ(readMesh(path).positions, mesh.positions);
}

TEST_F(VertexAttributesTest, MismatchedOrBadAttributesWriteNothing) {
  const TriangleMesh mesh = test::tetrahedron();
  VertexAttributes attributes = attributesFor(mesh);
  attributes.scalars.pop_back();
  const fs::path path = scratch_ / "d.ply";
  EXPECT_THROW(writeMesh(path, mesh, attributes), InputError);
  attributes = attributesFor(mesh);
  attributes.scalarName = "bad name";
  EXPECT_THROW(writeMesh(path, mesh, attributes), InputError);
  attributes = attributesFor(mesh);
  attributes.scalars[1] = std::nanf("");
  EXPECT_THROW(writeMesh(path, mesh, attributes), InputError);
  attributes = attributesFor(mesh);
  attributes.colors.resize(2);
  EXPECT_THROW(writeMesh(path, mesh, attributes), InputError);
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace d2vdb
