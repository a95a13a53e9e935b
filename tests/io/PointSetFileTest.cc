// Point files: .xyz round trips bit for bit, .ply vertices, and every malformed input rejected
// with a message naming the file and the line.
#include "d2vdb/io/PointSetFile.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "IoTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/MeshIO.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::InputError;
using Eigen::Vector3d;

using d2vdb::test::expectInputError;
using d2vdb::test::sameBits;

class PointSetFileTest : public d2vdb::test::ScratchDirectoryTest {};

TEST_F(PointSetFileTest, XyzRoundTripIsBitExact) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coordinate(-1e3, 1e3);
  std::vector<Vector3d> points = {Vector3d(0.1, 1.0 / 3.0, -0.0),
                                  Vector3d(5e-324, 1.7976931348623157e308, -2.5e-8),
                                  Vector3d(123456789.123456789, -1e-300, 7.0)};
  for (int i = 0; i < 200; ++i)
    points.emplace_back(coordinate(rng), coordinate(rng), coordinate(rng));
  d2vdb::writePointSet(file("cloud.xyz"), points);
  const std::vector<Vector3d> read = d2vdb::readPointSet(file("cloud.xyz"));
  ASSERT_EQ(read.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_TRUE(sameBits(read[i][axis], points[i][axis]))
          << "point " << i << " axis " << axis << ": " << read[i][axis];
    }
  }
  // One line per point, three fields each.
  std::ifstream in(file("cloud.xyz"));
  std::size_t lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  EXPECT_EQ(lines, points.size());
}

TEST_F(PointSetFileTest, XyzSkipsCommentsBlankLinesAndExtraColumns) {
  const std::string text =
      "# scanned points\r\n"
      "\n"
      "1 2 3\r\n"
      "  -4.5\t+5e-1   6   0 0 1   255 0 0  # normal and colour ignored\n"
      "   \t \n"
      "7 8 9 # last";  // no final newline
  const std::vector<Vector3d> points = d2vdb::parseXyz(text, "scan.xyz");
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[0], Vector3d(1, 2, 3));
  EXPECT_EQ(points[1], Vector3d(-4.5, 0.5, 6));
  EXPECT_EQ(points[2], Vector3d(7, 8, 9));
}

TEST_F(PointSetFileTest, MalformedXyzNamesFileAndLine) {
  expectInputError([] { d2vdb::parseXyz("1 2 3\n4 5\n", "cut.xyz"); },
                   {"point file 'cut.xyz', line 2", "found 2 values"});
  expectInputError([] { d2vdb::parseXyz("1 2 3\n\n# c\n4 nan 6\n", "nan.xyz"); },
                   {"'nan.xyz', line 4", "y coordinate 'nan' is not a finite number"});
  expectInputError([] { d2vdb::parseXyz("1 2 -inf\n", "inf.xyz"); },
                   {"line 1", "z coordinate '-inf'"});
  expectInputError([] { d2vdb::parseXyz("1 2 3\n1,5 2 3\n", "comma.xyz"); },
                   {"line 2", "x coordinate '1,5' is not a number"});
  expectInputError([] { d2vdb::parseXyz("1 2 3e999\n", "big.xyz"); },
                   {"line 1", "out of double range"});
  expectInputError([] { d2vdb::parseXyz("# nothing\n\n  \n", "empty.xyz"); },
                   {"'empty.xyz'", "contains no points"});
  expectInputError([] { d2vdb::parseXyz("", "zero.xyz"); }, {"contains no points"});
  expectInputError([&] { d2vdb::readPointSet(file("absent.xyz")); }, {"does not exist"});
  write("points.txt", "1 2 3\n");
  expectInputError([&] { d2vdb::readPointSet(file("points.txt")); }, {"'.txt'", ".xyz and .ply"});
}

TEST_F(PointSetFileTest, PlyVerticesAreReadWithOrWithoutFaces) {
  const fs::path cloud = write("cloud.ply",
                               "ply\nformat ascii 1.0\nelement vertex 3\n"
                               "property float x\nproperty float y\nproperty float z\n"
                               "property uchar red\nend_header\n"
                               "0.5 1 2 10\n-3 4.25 5 20\n6 7 -8 30\n");
  const std::vector<Vector3d> points = d2vdb::readPointSet(cloud);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[0], Vector3d(0.5, 1, 2));
  EXPECT_EQ(points[1], Vector3d(-3, 4.25, 5));
  EXPECT_EQ(points[2], Vector3d(6, 7, -8));

  // A mesh's vertices (binary PLY written by the mesh module), faces ignored.
  d2vdb::TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1.5f}};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  d2vdb::writeMesh(file("tet.PLY"), mesh);
  const std::vector<Vector3d> vertices = d2vdb::readPointSet(file("tet.PLY"));
  ASSERT_EQ(vertices.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(vertices[i], mesh.positions[i].cast<double>());

  write("nan.ply",
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n0 0 0\n1 nan 0\n");
  expectInputError([&] { d2vdb::readPointSet(file("nan.ply")); }, {"nan.ply", "line 9"});
  write("short.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n0 0 0\n1 1 0\n");
  expectInputError([&] { d2vdb::readPointSet(file("short.ply")); }, {"short.ply"});
}

TEST_F(PointSetFileTest, WriterRefusesBadInputAndKeepsExistingFile) {
  write("keep.xyz", "1 2 3\n");
  expectInputError([&] { d2vdb::writePointSet(file("keep.xyz"), {}); }, {"empty point set"});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expectInputError(
      [&] {
        d2vdb::writePointSet(file("keep.xyz"), {Vector3d(0, 0, 0), Vector3d(nan, 0, 0)});
      },
      {"point 1", "non-finite"});
  expectInputError([&] { d2vdb::writePointSet(file("cloud.ply"), {Vector3d(0, 0, 0)}); },
                   {"written as .xyz"});
  EXPECT_EQ(d2vdb::readPointSet(file("keep.xyz")), std::vector<Vector3d>{Vector3d(1, 2, 3)});
  EXPECT_FALSE(fs::exists(file("cloud.ply")));
  EXPECT_THROW(d2vdb::writePointSet(scratch_ / "missing-dir" / "a.xyz", {Vector3d(0, 0, 0)}),
               d2vdb::RuntimeFailure);
}

}  // namespace
