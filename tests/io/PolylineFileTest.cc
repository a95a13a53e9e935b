// Polyline JSON files and slice polyline files: bit-exact round trips, and every malformed input
// rejected with the file and the JSON path in the message.
#include "d2vdb/io/PolylineFile.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "IoTestSupport.h"
#include "d2vdb/core/Error.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::InputError;
using d2vdb::Polyline;
using Eigen::Vector3d;

using d2vdb::test::expectInputError;
using d2vdb::test::sameBits;

class PolylineFileTest : public d2vdb::test::ScratchDirectoryTest {};

void expectSamePolyline(const Polyline& a, const Polyline& b) {
  EXPECT_EQ(a.dimension, b.dimension);
  EXPECT_EQ(a.closed, b.closed);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_TRUE(sameBits(a.points[i][axis], b.points[i][axis]))
          << "point " << i << " axis " << axis << ": " << a.points[i][axis] << " vs "
          << b.points[i][axis];
    }
  }
}

TEST_F(PolylineFileTest, RoundTripsAreBitExactIn2DAnd3D) {
  Polyline helix;  // open 3D helix with awkward coordinates
  helix.dimension = 3;
  for (int i = 0; i < 50; ++i) {
    const double t = 0.1 * i;
    helix.points.emplace_back(std::cos(t) / 3.0, std::sin(t) * 1e-7, t * 1e300);
  }
  helix.points[0] = Vector3d(-0.0, 5e-324, 0.1);
  d2vdb::writePolyline(file("helix.json"), helix);
  expectSamePolyline(d2vdb::readPolyline(file("helix.json")), helix);

  Polyline square;  // closed 2D
  square.dimension = 2;
  square.closed = true;
  square.points = {Vector3d(0, 0, 0), Vector3d(1.0 / 3.0, 0, 0), Vector3d(1.0 / 3.0, 0.7, 0),
                   Vector3d(0, 0.7, 0)};
  d2vdb::writePolyline(file("square.json"), square);
  expectSamePolyline(d2vdb::readPolyline(file("square.json")), square);
  const nlohmann::json json = nlohmann::json::parse(std::ifstream(file("square.json")));
  EXPECT_EQ(json["type"], "polyline");
  EXPECT_EQ(json["version"], 1);
  EXPECT_EQ(json["dimension"], 2);
  EXPECT_EQ(json["closed"], true);
  ASSERT_EQ(json["points"].size(), 4u);
  EXPECT_EQ(json["points"][1].size(), 2u);  // [x, y] only
}

TEST_F(PolylineFileTest, HandWrittenFileDefaultsToOpen) {
  const std::vector<Polyline> lines = d2vdb::parsePolylines(
      R"({"type": "polyline", "version": 1, "dimension": 2, "points": [[0, 0], [1, 2], [3, 1e-3]]})");
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_FALSE(lines[0].closed);
  EXPECT_EQ(lines[0].dimension, 2);
  EXPECT_EQ(lines[0].points[2], Vector3d(3, 1e-3, 0));
}

TEST_F(PolylineFileTest, SliceFilesGiveEveryLineInPlaneCoordinates) {
  write("slice.json",
        R"({"axis": "z", "offset": 0.1, "iso": 0, "plane_axes": ["x", "y"],
                "polylines": [{"closed": true, "points": [[0, 0], [1, 0], [0.5, 0.75]]},
                              {"closed": false, "points": [[2, 2], [3, 2.5]]}]})");
  const std::vector<Polyline> lines = d2vdb::readPolylines(file("slice.json"));
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_TRUE(lines[0].closed);
  EXPECT_EQ(lines[0].dimension, 2);
  EXPECT_EQ(lines[0].points[2], Vector3d(0.5, 0.75, 0));
  EXPECT_FALSE(lines[1].closed);
  EXPECT_EQ(lines[1].points[1], Vector3d(3, 2.5, 0));
  expectInputError([&] { d2vdb::readPolyline(file("slice.json")); },
                   {"slice.json", "holds 2 polylines", "exactly one"});

  write("one.json", R"({"axis": "x", "offset": -1, "iso": 0.5, "plane_axes": ["y", "z"],
                           "polylines": [{"closed": false, "points": [[2, 2], [3, 2.5]]}]})");
  EXPECT_EQ(d2vdb::readPolyline(file("one.json")).points.size(), 2u);
  write("none.json",
        R"({"axis": "x", "offset": -1, "iso": 0, "plane_axes": ["y", "z"], "polylines": []})");
  EXPECT_TRUE(d2vdb::readPolylines(file("none.json")).empty());
  expectInputError([&] { d2vdb::readPolyline(file("none.json")); }, {"holds 0 polylines"});
}

TEST_F(PolylineFileTest, MalformedFilesNameFileAndField) {
  const auto parse = [](const std::string& text) { d2vdb::parsePolylines(text, "bad.json"); };
  const std::string head = R"({"type": "polyline", "version": 1, )";
  expectInputError([&] { parse(head + R"("dimension": 3, "points": [[0, 0, 0], [1, 1, 1]])"); },
                   {"polyline file 'bad.json'", "invalid JSON at byte"});  // truncated
  expectInputError([&] { parse(head + R"("dimension": 3, "points": [[0, 0, 0], [1, null, 1]]})"); },
                   {"field 'points[1][1]'", "expected a number, got null"});
  expectInputError([&] { parse(head + R"("dimension": 3, "points": [[0, 0, 0], [1, NaN, 1]]})"); },
                   {"invalid JSON"});
  expectInputError(
      [&] { parse(head + R"("dimension": 3, "points": [[0, 0, 0], [1, 1e999, 1]]})"); },
      {"bad.json"});
  expectInputError([&] { parse(head + R"("dimension": 3, "points": [[0, 0, 0], [1, 1]]})"); },
                   {"field 'points[1]'", "has 2 coordinates, expected 3"});
  expectInputError([&] { parse(head + R"("dimension": 4, "points": [[0, 0], [1, 1]]})"); },
                   {"field 'dimension'", "dimension 4 is not supported"});
  expectInputError(
      [&] { parse(head + R"("dimension": 2, "colour": "red", "points": [[0, 0], [1, 1]]})"); },
      {"field 'colour'", "is not a field of a polyline"});
  expectInputError([&] { parse(head + R"("dimension": 2, "points": []})"); },
                   {"field 'points'", "has 0 points"});
  expectInputError(
      [&] { parse(head + R"("dimension": 2, "closed": true, "points": [[0, 0], [1, 1]]})"); },
      {"field 'points'", "closed polyline needs at least 3"});
  expectInputError(
      [&] { parse(head + R"("dimension": 2, "closed": 1, "points": [[0, 0], [1, 1]]})"); },
      {"field 'closed'", "expected true or false"});
  expectInputError([&] { parse(head + R"("points": [[0, 0], [1, 1]]})"); },
                   {"field 'dimension'", "is missing"});
  expectInputError([&] { parse(R"({"type": "bspline_curve", "version": 1})"); },
                   {"field 'type'", "expected \"polyline\""});
  expectInputError([&] { parse(R"({"type": "polyline", "version": 2})"); },
                   {"field 'version'", "version 2 is not supported"});
  expectInputError([&] { parse("[1, 2]"); }, {"expected a JSON object, got an array"});
  expectInputError([&] { parse(""); }, {"invalid JSON"});
  // Slice files are checked as strictly.
  const std::string slice = R"({"axis": "z", "offset": 0, "iso": 0, "plane_axes": ["x", "y"], )";
  expectInputError(
      [&] {
        parse(slice + R"("polylines": [{"closed": true, "points": [[0, 0], [1, 0], [1, 1, 0]]}]})");
      },
      {"field 'polylines[0].points[2]'", "has 3 coordinates, expected 2"});
  expectInputError([&] { parse(slice + R"("polylines": [{"points": [[0, 0], [1, 0]]}]})"); },
                   {"field 'polylines[0].closed'", "is missing"});
  expectInputError(
      [&] {
        parse(slice + R"("polylines": [{"closed": false, "points": [[0, 0], [1, 0]], "z": 1}]})");
      },
      {"field 'polylines[0].z'", "is not a field"});
  expectInputError(
      [&] {
        parse(R"({"axis": "w", "offset": 0, "iso": 0, "plane_axes": ["x", "y"], "polylines": []})");
      },
      {"field 'axis'", "\"w\""});
  // Plane axes must be two distinct axis names other than the slice's axis.
  for (const char* axes : {R"(["x", "1"])", R"(["x", "x"])", R"(["z", "y"])"}) {
    expectInputError(
        [&] {
          parse(std::string(R"({"axis": "z", "offset": 0, "iso": 0, "plane_axes": )") + axes +
                R"(, "polylines": []})");
        },
        {"field 'plane_axes[", "two other axes"});
  }
  // Duplicate keys anywhere, named by their path (the element index inside arrays too).
  expectInputError([&] { parse(head + R"("dimension": 2, "dimension": 3, "points": []})"); },
                   {"field 'dimension'", "appears twice"});
  expectInputError(
      [&] {
        parse(slice + R"("polylines": [{"closed": true, "points": [[0, 0], [1, 0], [1, 1]]}, )" +
              R"({"closed": false, "points": [[0, 0], [1, 0]], "closed": true}]})");
      },
      {"field 'polylines[1].closed'", "appears twice"});
  expectInputError([&] { d2vdb::readPolylines(file("absent.json")); },
                   {"polyline file", "does not exist"});
}

TEST_F(PolylineFileTest, WriterRefusesBadPolylinesAndKeepsExistingFile) {
  write("keep.json", "old");
  Polyline flat;
  flat.dimension = 2;
  flat.points = {Vector3d(0, 0, 0), Vector3d(1, 1, 0.5)};
  expectInputError([&] { d2vdb::writePolyline(file("keep.json"), flat); }, {"point 1", "z is 0.5"});
  Polyline nan;
  nan.points = {Vector3d(0, 0, 0), Vector3d(std::numeric_limits<double>::infinity(), 0, 0)};
  expectInputError([&] { d2vdb::writePolyline(file("keep.json"), nan); }, {"non-finite"});
  Polyline single;
  single.points = {Vector3d(0, 0, 0)};
  expectInputError([&] { d2vdb::writePolyline(file("keep.json"), single); }, {"1 points"});
  Polyline fourD;
  fourD.dimension = 4;
  fourD.points = {Vector3d(0, 0, 0), Vector3d(1, 0, 0)};
  expectInputError([&] { d2vdb::writePolyline(file("keep.json"), fourD); }, {"dimension 4"});
  std::ifstream in(file("keep.json"));
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "old");
}

}  // namespace
