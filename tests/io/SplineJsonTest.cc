#include "d2vdb/io/SplineJson.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"
#include "io/IoTestSupport.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::BSplineCurve;
using d2vdb::BSplineSurface;
using d2vdb::InputError;
using d2vdb::KnotVector;
using Eigen::Vector3d;

using d2vdb::test::sameBits;

void expectSamePoints(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_TRUE(sameBits(a[i][axis], b[i][axis]))
          << "point " << i << " axis " << axis << ": " << a[i][axis] << " vs " << b[i][axis];
    }
  }
}

void expectSameKnots(const KnotVector& a, const KnotVector& b) {
  ASSERT_EQ(a.degree(), b.degree());
  ASSERT_EQ(a.size(), b.size());
  for (int i = 0; i < a.size(); ++i) EXPECT_TRUE(sameBits(a[i], b[i])) << "knot " << i;
}

// Coordinates that stress round-tripping: non-terminating binary fractions, extremes, -0.
std::vector<Vector3d> awkwardPoints(int count, bool planar) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  const double special[] = {
      0.1, 1.0 / 3.0, -0.0, 1e-300, 5e-324, 1.7976931348623157e308, -2.5e-8, 123456789.123456789};
  std::vector<Vector3d> points;
  for (int i = 0; i < count; ++i) {
    Vector3d point(coordinate(rng), coordinate(rng), planar ? 0.0 : coordinate(rng));
    point.x() = i < 8 ? special[i] : point.x();
    points.push_back(point);
  }
  return points;
}

std::string errorOf(const std::string& text) {
  try {
    d2vdb::parseSplineJson(text, "test.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

// Expects parsing `text` to fail with a message naming test.json and every fragment.
void expectRejected(const std::string& text, const std::vector<std::string>& fragments) {
  const std::string message = errorOf(text);
  EXPECT_NE(message.find("spline file 'test.json'"), std::string::npos) << message;
  for (const std::string& fragment : fragments) {
    EXPECT_NE(message.find(fragment), std::string::npos)
        << "missing '" << fragment << "' in: " << message;
  }
}

const char* const kValidCurve = R"({
  "type": "bspline_curve", "version": 1, "dimension": 2, "degree": 2, "closed": false,
  "knots": [0, 0, 0, 0.5, 1, 1, 1],
  "control_points": [[0, 0], [1, 2], [2, 2], [3, 0]]
})";

// kValidCurve with `from` replaced by `to` (each must occur).
std::string curveWith(const std::string& from, const std::string& to) {
  std::string text = kValidCurve;
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

const char* const kValidSurface = R"({
  "type": "bspline_surface", "version": 1, "degree_u": 1, "degree_v": 2,
  "knots_u": [0, 0, 0.5, 1, 1], "knots_v": [0, 0, 0, 1, 1, 1],
  "control_points": [[[0, 0, 0], [0, 1, 1], [0, 2, 0]], [[1, 0, 0], [1, 1, 2], [1, 2, 0]], [[2, 0, 0], [2, 1, 1], [2, 2, 0]]]
})";

std::string surfaceWith(const std::string& from, const std::string& to) {
  std::string text = kValidSurface;
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

class SplineJsonFiles : public d2vdb::test::ScratchDirectoryTest {};

TEST(SplineJson, OpenCurveRoundTripIsBitExact) {
  for (const int dimension : {2, 3}) {
    std::vector<double> knots{-0.1, 0.0, 0.0, 1.0 / 3.0, 1.0 / 3.0, 0.7, 1.1, 1.1, 2.0};
    const BSplineCurve curve(KnotVector(3, knots), awkwardPoints(5, dimension == 2), dimension);
    const std::string text = d2vdb::curveToJson(curve);
    const BSplineCurve read = d2vdb::parseCurveJson(text);
    EXPECT_EQ(read.dimension(), dimension);
    EXPECT_FALSE(read.isClosed());
    expectSameKnots(read.knots(), curve.knots());
    expectSamePoints(read.controlPoints(), curve.controlPoints());
    EXPECT_EQ(d2vdb::curveToJson(read), text);
    // The documented layout: dimension coordinates per point.
    const nlohmann::json json = nlohmann::json::parse(text);
    EXPECT_EQ(json["type"], "bspline_curve");
    EXPECT_EQ(json["version"], 1);
    EXPECT_EQ(json["control_points"].size(), 5u);
    EXPECT_EQ(json["control_points"][0].size(), static_cast<std::size_t>(dimension));
    EXPECT_EQ(json["knots"].size(), knots.size());
  }
}

TEST(SplineJson, ClosedCurveStoresUniquePointsAndItsPeriodicKnots) {
  const BSplineCurve curve = BSplineCurve::closed(3, awkwardPoints(6, true), 2, {0.1, 0.7});
  const std::string text = d2vdb::curveToJson(curve);
  const nlohmann::json json = nlohmann::json::parse(text);
  EXPECT_EQ(json["closed"], true);
  EXPECT_EQ(json["control_points"].size(), 6u);
  EXPECT_EQ(json["knots"].size(), 6u + 2 * 3 + 1);
  const BSplineCurve read = d2vdb::parseCurveJson(text);
  EXPECT_TRUE(read.isClosed());
  expectSameKnots(read.knots(), curve.knots());
  expectSamePoints(read.controlPoints(), curve.controlPoints());
  for (int k = 0; k <= 10; ++k) {
    const double t = curve.domain().at(k / 10.0);
    EXPECT_EQ(read.evaluate(t), curve.evaluate(t));
  }
}

TEST(SplineJson, SurfaceRoundTripIsBitExactIncludingClosedDirections) {
  const std::vector<Vector3d> points = awkwardPoints(5 * 5, false);
  const BSplineSurface surface(KnotVector::periodic(2, 5, {0.0, 0.3}),
                               KnotVector(1, {0.0, 0.0, 0.1, 0.2, 1.0 / 7.0 + 0.5, 1.0, 1.0}),
                               points, true, false);
  const std::string text = d2vdb::surfaceToJson(surface);
  const BSplineSurface read = d2vdb::parseSurfaceJson(text);
  EXPECT_TRUE(read.isClosedU());
  EXPECT_FALSE(read.isClosedV());
  EXPECT_EQ(read.countU(), 5);
  EXPECT_EQ(read.countV(), 5);
  expectSameKnots(read.knotsU(), surface.knotsU());
  expectSameKnots(read.knotsV(), surface.knotsV());
  expectSamePoints(read.controlPoints(), surface.controlPoints());
  // control_points[i][j] is P_ij with i along u.
  const nlohmann::json json = nlohmann::json::parse(text);
  ASSERT_EQ(json["control_points"].size(), 5u);
  ASSERT_EQ(json["control_points"][0].size(), 5u);
  EXPECT_EQ(json["control_points"][2][3][1].get<double>(), surface.controlPoint(2, 3).y());
}

TEST(SplineJson, HandWrittenFilesParseWithDefaults) {
  const BSplineCurve curve = d2vdb::parseCurveJson(curveWith(R"("closed": false,)", ""));
  EXPECT_FALSE(curve.isClosed());
  EXPECT_EQ(curve.dimension(), 2);
  EXPECT_EQ(curve.evaluate(0.0), Vector3d(0, 0, 0));
  EXPECT_EQ(curve.evaluate(1.0), Vector3d(3, 0, 0));
  const BSplineSurface surface = d2vdb::parseSurfaceJson(kValidSurface);
  EXPECT_FALSE(surface.isClosedU());
  EXPECT_EQ(surface.controlPoint(1, 1), Vector3d(1, 1, 2));
  EXPECT_TRUE(std::holds_alternative<BSplineSurface>(d2vdb::parseSplineJson(kValidSurface)));
  EXPECT_TRUE(std::holds_alternative<BSplineCurve>(d2vdb::parseSplineJson(kValidCurve)));
}

TEST(SplineJson, MalformedCurvesAreRejectedNamingTheField) {
  expectRejected("{\"type\": \"bspline_curve\",,}", {"invalid JSON at byte 26"});
  expectRejected("[1, 2]", {"expected a JSON object, got an array"});
  expectRejected(curveWith("[0, 0, 0, 0.5", "[0, 0, 0, 1e999"), {"invalid JSON", "1e999"});
  expectRejected(curveWith(R"("type": "bspline_curve")", R"("type": "nurbs")"),
                 {"field 'type'", "\"nurbs\""});
  expectRejected(curveWith(R"("version": 1)", R"("version": 2)"),
                 {"field 'version'", "version 2 is not supported"});
  expectRejected(curveWith(R"("degree": 2,)", ""), {"field 'degree'", "is missing"});
  expectRejected(curveWith(R"("degree": 2)", R"("degree": "2")"),
                 {"field 'degree'", "expected an integer, got a string"});
  expectRejected(curveWith(R"("degree": 2)", R"("degree": 2.0)"),
                 {"field 'degree'", "expected an integer, got a number"});
  expectRejected(curveWith(R"("degree": 2)", R"("degree": 16)"),
                 {"field 'degree'", "degree 16 is not supported"});
  expectRejected(curveWith(R"("dimension": 2)", R"("dimension": 4)"),
                 {"field 'dimension'", "expected 2 or 3"});
  expectRejected(curveWith(R"("closed": false)", R"("closed": "no")"),
                 {"field 'closed'", "expected true or false, got a string"});
  expectRejected(curveWith(R"("closed": false)", R"("colsed": false)"),
                 {"field 'colsed'", "is not a field of a bspline_curve"});
  expectRejected(curveWith("[0, 0, 0, 0.5, 1, 1, 1]", "7"),
                 {"field 'knots'", "expected an array, got a number"});
  expectRejected(curveWith("[0, 0, 0, 0.5", "[0, 0, null, 0.5"),
                 {"field 'knots[2]'", "expected a number, got null"});
  expectRejected(curveWith("[0, 0, 0, 0.5, 1", "[0, 0, 0, 1.5, 1"),
                 {"field 'knots'", "non-decreasing", "knot 4 (1) is less than knot 3 (1.5)"});
  expectRejected(curveWith("[0, 0, 0, 0.5, 1", "[0, 0, 0, 0, 1"),
                 {"field 'knots'", "knot value 0 occurs 4 times"});
  expectRejected(curveWith("[1, 2], [2, 2]", "[1, 2, 5], [2, 2]"),
                 {"field 'control_points[1]'", "has 3 coordinates, expected 2"});
  expectRejected(curveWith("[1, 2], [2, 2]", "[null, 2], [2, 2]"),
                 {"field 'control_points[1][0]'", "expected a number, got null"});
  expectRejected(curveWith("[1, 2], [2, 2]", "[1, 2], {\"x\": 2}"),
                 {"field 'control_points[2]'", "expected an array, got an object"});
  expectRejected(curveWith(", [3, 0]]", "]"), {"field 'control_points'", "has 3 points", "need 4"});
  expectRejected(curveWith("\"control_points\"", "\"points\""),
                 {"field 'points'", "is not a field"});
  // Duplicate keys: nlohmann would keep the last one silently.
  expectRejected(curveWith(R"("degree": 2)", R"("degree": 2, "degree": 3)"),
                 {"field 'degree'", "appears twice"});
}

TEST(SplineJson, MalformedClosedCurvesAreRejected) {
  const std::string closed = curveWith(R"("closed": false)", R"("closed": true)");
  // 4 unique points of degree 2 need 4 + 2 * 2 + 1 = 9 knots.
  expectRejected(closed, {"field 'knots'", "needs 9 knots", "got 7"});
  std::string uneven = closed;
  uneven.replace(uneven.find("[0, 0, 0, 0.5, 1, 1, 1]"), 23,
                 "[-0.5, -0.25, 0, 0.25, 0.5, 0.8, 1, 1.25, 1.5]");
  expectRejected(uneven, {"field 'knots'", "uniform periodic"});
  std::string uniform = closed;
  uniform.replace(uniform.find("[0, 0, 0, 0.5, 1, 1, 1]"), 23,
                  "[-0.5, -0.25, 0, 0.25, 0.5, 0.75, 1, 1.25, 1.5]");
  const BSplineCurve curve = d2vdb::parseCurveJson(uniform);
  EXPECT_TRUE(curve.isClosed());
  EXPECT_LT((curve.evaluate(0.0) - curve.evaluate(1.0)).norm(), 1e-15);
}

TEST(SplineJson, MalformedSurfacesAreRejectedNamingTheField) {
  expectRejected(surfaceWith(R"("degree_v": 2)", R"("degree_v": 0)"),
                 {"field 'degree_v'", "degree 0 is not supported"});
  expectRejected(surfaceWith(R"("knots_u": [0, 0, 0.5, 1, 1], )", ""),
                 {"field 'knots_u'", "is missing"});
  expectRejected(surfaceWith(", [[2, 0, 0], [2, 1, 1], [2, 2, 0]]", ""),
                 {"field 'control_points'", "has 2 rows", "needs 3"});
  expectRejected(surfaceWith("[[1, 0, 0], [1, 1, 2], [1, 2, 0]]", "[[1, 0, 0], [1, 1, 2]]"),
                 {"field 'control_points[1]'", "has 2 points", "needs 3"});
  expectRejected(surfaceWith("[0, 1, 1]", "[0, 1]"),
                 {"field 'control_points[0][1]'", "has 2 coordinates, expected 3"});
  expectRejected(surfaceWith("[1, 1, 2]", "[1, 1, null]"),
                 {"field 'control_points[1][1][2]'", "expected a number, got null"});
  expectRejected(surfaceWith(R"("degree_u": 1)", R"("degree_u": 1, "closed_u": true)"),
                 {"field 'knots_u'", "uniform periodic"});
  expectRejected(surfaceWith(R"("type": "bspline_surface")", R"("type": "bspline_curve")"),
                 {"field 'degree_u'", "is not a field of a bspline_curve"});
  expectRejected(surfaceWith(R"("type": "bspline_surface")", R"("type": "mesh")"),
                 {"field 'type'", "expected \"bspline_curve\" or \"bspline_surface\""});
}

TEST_F(SplineJsonFiles, FileRoundTripAndTypeDispatch) {
  const BSplineCurve curve = BSplineCurve::clamped(3, awkwardPoints(7, false));
  const fs::path curveFile = scratch_ / "curve.json";
  d2vdb::writeCurveJson(curveFile, curve);
  const BSplineCurve read = d2vdb::readCurveJson(curveFile);
  expectSameKnots(read.knots(), curve.knots());
  expectSamePoints(read.controlPoints(), curve.controlPoints());
  EXPECT_TRUE(std::holds_alternative<BSplineCurve>(d2vdb::readSplineJson(curveFile)));

  const BSplineSurface surface = d2vdb::parseSurfaceJson(kValidSurface);
  const fs::path surfaceFile = scratch_ / "surface.json";
  d2vdb::writeSurfaceJson(surfaceFile, surface);
  expectSamePoints(d2vdb::readSurfaceJson(surfaceFile).controlPoints(), surface.controlPoints());
  EXPECT_TRUE(std::holds_alternative<BSplineSurface>(d2vdb::readSplineJson(surfaceFile)));
  // Reading a surface file as a curve names the file and the mismatching type.
  try {
    d2vdb::readCurveJson(surfaceFile);
    FAIL();
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(surfaceFile.string()), std::string::npos) << message;
    EXPECT_NE(message.find("field 'type'"), std::string::npos) << message;
  }
}

TEST_F(SplineJsonFiles, MissingFilesAndBadTargetsAreReported) {
  const fs::path missing = scratch_ / "missing.json";
  try {
    d2vdb::readCurveJson(missing);
    FAIL();
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(missing.string()), std::string::npos) << message;
    EXPECT_NE(message.find("does not exist"), std::string::npos) << message;
  }
  EXPECT_THROW(d2vdb::readSurfaceJson(scratch_), InputError);
  const fs::path broken = scratch_ / "broken.json";
  std::ofstream(broken) << "{\"type\": ";
  try {
    d2vdb::readSplineJson(broken);
    FAIL();
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("spline file '" + broken.string() + "': invalid JSON at byte"),
              std::string::npos)
        << message;
  }
  const BSplineCurve curve = BSplineCurve::clamped(1, {{0, 0, 0}, {1, 0, 0}});
  EXPECT_THROW(d2vdb::writeCurveJson(scratch_ / "no" / "such" / "c.json", curve),
               d2vdb::RuntimeFailure);
}

}  // namespace
