// Malformed mesh files: every case must be an InputError naming the file and the line (text) or
// byte offset (binary) of the problem, never a crash or a partial mesh.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "d2vdb/mesh/MeshIO.h"
#include "mesh/MeshTestSupport.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::ByteWriter;

struct MalformedCase {
  std::string fileName;
  std::string contents;
  std::vector<std::string> fragments;  ///< besides the file name, the message must contain these
};

class MeshIOErrorTest : public d2vdb::test::ScratchDirectoryTest {
 protected:
  void expectAllRejected(const std::vector<MalformedCase>& cases) {
    for (const MalformedCase& malformed : cases) {
      SCOPED_TRACE(malformed.fileName);
      const fs::path path = write(malformed.fileName, malformed.contents);
      try {
        const d2vdb::TriangleMesh mesh = d2vdb::readMesh(path);
        ADD_FAILURE() << "read " << mesh.vertexCount() << " vertices instead of failing";
      } catch (const d2vdb::InputError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find(path.string()), std::string::npos) << message;
        for (const std::string& fragment : malformed.fragments) {
          EXPECT_NE(message.find(fragment), std::string::npos)
              << "message \"" << message << "\" lacks \"" << fragment << "\"";
        }
      }
    }
  }
};

const std::string kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST_F(MeshIOErrorTest, MalformedObj) {
  expectAllRejected({
      {"empty.obj", "", {"empty"}},
      {"comments_only.obj", "# nothing here\n\n", {"no vertices"}},
      {"zero_index.obj", kTriangleObj + "f 0 1 2\n", {"line 4:", "index 0"}},
      {"index_too_big.obj", kTriangleObj + "f 1 2 4\n", {"line 4:", "vertex index 4", "range"}},
      {"forward_index.obj",
       "f 1 2 9\n" + kTriangleObj,
       {"line 1:", "vertex index 9", "defines 3 vertices)"}},
      // A face naming a vertex far beyond what the file defines, with a normal: refused without
      // allocating by the index (found by fuzzing: 400 MB for this 20-byte file).
      {"forward_index_with_normal.obj",
       "f 103666610//1 3 7\n" + kTriangleObj + "vn 0 0 1\n",
       {"line 1:", "vertex index 103666610", "defines 3 vertices)"}},
      {"relative_too_far.obj", kTriangleObj + "f -4 -2 -1\n", {"line 4:", "-4"}},
      {"normal_index_too_big.obj",
       kTriangleObj + "vn 0 0 1\nf 1//2 2//2 3//2\n",
       {"line 5:", "normal index 2"}},
      {"texture_index_zero.obj",
       kTriangleObj + "vt 0 0\nf 1/0 2/1 3/1\n",
       {"line 5:", "texture coordinate index 0"}},
      {"nan.obj", "v 0 0 0\nv nan 1 0\nv 0 1 0\nf 1 2 3\n", {"line 2:", "'nan'", "not finite"}},
      {"inf.obj", "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n", {"line 3:", "not finite"}},
      {"huge.obj", "v 0 1e39 0\n", {"line 1:", "out of range"}},
      {"word.obj", "v 1 x 0\n", {"line 1:", "'x'", "not a number"}},
      {"trailing_word.obj", "v 1 2 3 w\n", {"line 1:", "'w'"}},
      {"word_index.obj", kTriangleObj + "f 1 a 3\n", {"line 4:", "'a'"}},
      {"two_corners.obj", kTriangleObj + "f 1 2\n", {"line 4:", "2 corners", "at least 3"}},
      {"short_vertex.obj", "v 0 0 0\nv 1 2\n", {"line 2:", "3 are needed"}},
      {"unknown.obj", "v 0 0 0\nbogus 1 2\n", {"line 2:", "'bogus'"}},
      {"freeform.obj", "v 0 0 0\ncurv 0 1 1\n", {"line 2:", "free-form"}},
      {"bad_corner.obj", kTriangleObj + "f 1/ 2 3\n", {"line 4:", "'1/'"}},
      {"binary.obj", std::string("\x7F\x45LF\x02\x01", 6), {"line 1:"}},
  });
}

/// An ASCII PLY triangle; lines 10-12 are the vertices and line 13 the face.
std::string asciiPly(const std::string& headerLines, const std::string& body) {
  return "ply\nformat ascii 1.0\n" + headerLines + "end_header\n" + body;
}
const std::string kPlyHeader =
    "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\n";
const std::string kPlyBody = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

TEST_F(MeshIOErrorTest, MalformedAsciiPly) {
  expectAllRejected({
      {"empty.ply", "", {"empty"}},
      {"not_ply.ply", "solid x\nfacet\n", {"line 1:", "not a PLY file"}},
      {"no_end_header.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n",
       {"line 5:", "end_header"}},
      {"bad_format.ply",
       "ply\nformat binary_middle_endian 1.0\n" + kPlyHeader + "end_header\n",
       {"line 2:", "binary_middle_endian"}},
      {"bad_version.ply",
       "ply\nformat ascii 2.0\n" + kPlyHeader + "end_header\n",
       {"line 2:", "'2.0'"}},
      {"bad_type.ply",
       asciiPly("element vertex 3\nproperty float33 x\nproperty float y\nproperty float z\n",
                kPlyBody),
       {"line 4:", "'float33'"}},
      {"no_z.ply",
       asciiPly("element vertex 3\nproperty float x\nproperty float y\nproperty float w\n",
                "0 0 0\n1 0 0\n0 1 0\n"),
       {"line 3:", "'z'"}},
      {"no_indices.ply",
       asciiPly("element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 1\nproperty list uchar int corners\n",
                kPlyBody),
       {"line 7:", "vertex_indices"}},
      {"no_vertices.ply",
       asciiPly("element vertex 0\nproperty float x\nproperty float y\nproperty float z\n", ""),
       {"no vertices"}},
      {"strips.ply",
       asciiPly(kPlyHeader + "element tristrips 1\nproperty list int int vertex_indices\n",
                kPlyBody + "4 0 1 2 0\n"),
       {"line 9:", "tristrips"}},
      {"bad_keyword.ply",
       "ply\nformat ascii 1.0\nelements vertex 3\nend_header\n",
       {"line 3:", "'elements'"}},
      {"too_few_faces.ply",
       asciiPly("element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 2\nproperty list uchar int vertex_indices\n",
                kPlyBody),
       {"line 13:", "1 of 2 'face' records"}},
      {"too_few_vertices.ply",
       asciiPly("element vertex 4\nproperty float x\nproperty float y\nproperty float z\n",
                "0 0 0\n1 0 0\n0 1 0\n"),
       {"line 10:", "3 of 4 'vertex' records"}},
      {"extra_data.ply",
       asciiPly(kPlyHeader, kPlyBody + "3 0 1 2\n"),
       {"line 14:", "after the last element"}},
      {"extra_value.ply",
       asciiPly(kPlyHeader, "0 0 0\n1 0 0 7\n0 1 0\n3 0 1 2\n"),
       {"line 11:", "'7'"}},
      {"too_few_values.ply",
       asciiPly(kPlyHeader, "0 0 0\n1 0\n0 1 0\n3 0 1 2\n"),
       {"line 11:", "too few values"}},
      {"index_too_big.ply",
       asciiPly(kPlyHeader, "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
       {"line 13:", "vertex index 3"}},
      {"negative_index.ply",
       asciiPly(kPlyHeader, "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"),
       {"line 13:", "negative"}},
      {"two_corners.ply",
       asciiPly(kPlyHeader, "0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
       {"line 13:", "at least 3"}},
      {"count_out_of_range.ply",
       asciiPly(kPlyHeader, "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n"),
       {"line 13:", "out of range for uchar"}},
      {"nan.ply",
       asciiPly(kPlyHeader, "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"),
       {"line 11:", "not finite"}},
      {"inf.ply",
       asciiPly(kPlyHeader, "0 0 0\n1 0 0\n0 1 inf\n3 0 1 2\n"),
       {"line 12:", "not finite"}},
      {"word.ply",
       asciiPly(kPlyHeader, "0 0 0\n1 0 0\n0 one 0\n3 0 1 2\n"),
       {"line 12:", "'one'", "not a number"}},
      {"word_index.ply",
       asciiPly(kPlyHeader, "0 0 0\n1 0 0\n0 1 0\n3 0 1 two\n"),
       {"line 13:", "'two'"}},
  });
}

/// Header of a binary little-endian PLY triangle (3 float vertices, one uchar/int face).
const std::string kBinaryPlyHeader =
    "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
    "property float y\nproperty float z\nelement face 1\n"
    "property list uchar int vertex_indices\nend_header\n";

/// The binary triangle with an optional replacement for vertex 1's y and for the third index.
std::string binaryPly(float vertexOneY = 0.0f, std::int32_t thirdIndex = 2) {
  ByteWriter file;
  file.text(kBinaryPlyHeader);
  file.f32(0).f32(0).f32(0).f32(1).f32(vertexOneY).f32(0).f32(0).f32(1).f32(0);
  file.u8(3).i32(0).i32(1).i32(thirdIndex);
  return file.bytes();
}

TEST_F(MeshIOErrorTest, MalformedBinaryPly) {
  const std::size_t body = kBinaryPlyHeader.size();
  const std::string good = binaryPly();
  ASSERT_EQ(good.size(), body + 36 + 13);
  const auto at = [](std::size_t offset) { return "byte " + std::to_string(offset) + ":"; };
  expectAllRejected({
      {"truncated_in_face.ply",
       good.substr(0, good.size() - 2),
       {at(body + 45), "middle of 'face' record 0"}},
      {"truncated_before_face.ply", good.substr(0, body + 36), {at(body + 36), "0 of 1 'face'"}},
      {"truncated_in_vertex.ply", good.substr(0, body + 14), {at(body + 12), "'vertex' record 1"}},
      {"extra_bytes.ply", good + "abc", {at(body + 49), "3 unexpected bytes"}},
      {"nan.ply",
       binaryPly(std::numeric_limits<float>::quiet_NaN()),
       {at(body + 16), "y coordinate", "not finite"}},
      {"inf.ply", binaryPly(-std::numeric_limits<float>::infinity()), {at(body + 16)}},
      {"index_too_big.ply", binaryPly(0.0f, 3), {at(body + 45), "vertex index 3"}},
      {"negative_index.ply", binaryPly(0.0f, -7), {at(body + 45), "negative"}},
  });
}

/// An ASCII STL triangle, lines 1 to 9.
std::string asciiStl(const std::vector<std::string>& replaceLines = {}) {
  std::vector<std::string> lines = {"solid t",      "facet normal 0 0 1", "outer loop",
                                    "vertex 0 0 0", "vertex 1 0 0",       "vertex 0 1 0",
                                    "endloop",      "endfacet",           "endsolid t"};
  for (std::size_t i = 0; i < replaceLines.size() && i < lines.size(); ++i) {
    if (!replaceLines[i].empty()) lines[i] = replaceLines[i];
  }
  std::string text;
  for (const std::string& line : lines) {
    if (line != "-") text += line + "\n";
  }
  return text;
}

TEST_F(MeshIOErrorTest, MalformedAsciiStl) {
  expectAllRejected({
      {"empty.stl", "", {"empty"}},
      {"no_endsolid.stl", asciiStl({"", "", "", "", "", "", "", "", "-"}), {"line 8:", "endsolid"}},
      {"truncated_facet.stl",
       asciiStl({"", "", "", "", "", "-", "-", "-", "-"}),
       {"line 5:", "truncated"}},
      {"word.stl", asciiStl({"", "", "", "", "vertex 1 zero 0"}), {"line 5:", "'zero'"}},
      {"nan.stl", asciiStl({"", "", "", "", "", "vertex 0 NaN 0"}), {"line 6:", "not finite"}},
      {"huge.stl", asciiStl({"", "", "", "vertex 0 0 -1e300"}), {"line 4:", "out of range"}},
      {"four_vertices.stl",
       asciiStl({"", "", "", "", "", "vertex 0 1 0\nvertex 1 1 0", "", "", ""}),
       {"line 7:", "more than 3 vertices"}},
      {"two_vertices.stl", asciiStl({"", "", "", "", "", "-"}), {"line 6:", "2 vertices"}},
      {"bad_keyword.stl", asciiStl({"", "", "outer lop"}), {"line 3:", "'loop'", "'lop'"}},
      {"bad_normal.stl", asciiStl({"", "facet normal 0 zero 1"}), {"line 2:", "'zero'"}},
      {"nan_normal.stl", asciiStl({"", "facet normal nan 0 1"}), {"line 2:", "not finite"}},
      {"inf_normal.stl", asciiStl({"", "facet normal 0 -inf 1"}), {"line 2:", "not finite"}},
      {"no_facets.stl", "solid nothing\nendsolid nothing\n", {"line 2:", "no facets"}},
      {"garbage_after.stl", asciiStl() + "hello\n", {"line 10:", "'hello'"}},
  });
}

/// A binary STL with `declared` in the count field and the given facets' corner coordinates.
std::string binaryStl(const std::string& header, std::uint32_t declared,
                      const std::vector<float>& coordinates) {
  ByteWriter file;
  std::string padded = header;
  padded.resize(80, '\0');
  file.text(padded).u32(declared);
  for (std::size_t i = 0; i < coordinates.size(); i += 9) {
    file.f32(0).f32(0).f32(1);
    for (std::size_t k = 0; k < 9; ++k) file.f32(coordinates[i + k]);
    file.u16(0);
  }
  return file.bytes();
}

TEST_F(MeshIOErrorTest, MalformedBinaryStl) {
  const std::vector<float> triangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::vector<float> withNan = triangle;
  withNan[4] = std::numeric_limits<float>::quiet_NaN();  // corner 1, y
  expectAllRejected({
      {"short.stl", "abc", {"3 bytes", "too short"}},
      {"count_mismatch.stl",
       binaryStl("binary", 2, triangle),
       {"byte 80:", "declares 2 triangles", "134 bytes", "truncated"}},
      {"extra_data.stl", binaryStl("binary", 1, triangle) + "xx", {"byte 80:", "extra data"}},
      {"truncated_solid_header.stl",
       binaryStl("solid but binary", 3, triangle),
       {"byte 80:", "declares 3 triangles"}},
      {"zero_triangles.stl", binaryStl("binary", 0, {}), {"byte 80:", "no triangles"}},
      {"nan.stl", binaryStl("binary", 1, withNan), {"byte 112:", "triangle 0", "not finite"}},
  });
  // A non-finite facet normal (the first 12 bytes of a facet) is rejected as well.
  std::string nanNormal =
      binaryStl("binary", 2, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1});
  const float infinity = std::numeric_limits<float>::infinity();
  std::memcpy(nanNormal.data() + 84 + 50 + 4, &infinity, 4);  // facet 1, normal y
  expectAllRejected({{"inf_normal.stl", nanNormal, {"byte 138:", "normal of triangle 1"}}});
}

}  // namespace
