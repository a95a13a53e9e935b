#include "d2vdb/io/SplineJson.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <utility>
#include <vector>

#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/io/detail/JsonDocuments.h"
#include "d2vdb/io/detail/JsonReader.h"
#include "d2vdb/io/detail/TextFile.h"

namespace d2vdb {
namespace {

using Json = detail::Json;

constexpr int kSplineFormatVersion = 1;
constexpr const char* kCurveType = "bspline_curve";
constexpr const char* kSurfaceType = "bspline_surface";

// Validates one parsed JSON document against the format, reporting errors with the source name
// and the JSON path of the offending field.
class SplineReader : public detail::JsonFieldReader {
 public:
  explicit SplineReader(std::string sourceName)
      : JsonFieldReader("spline file", std::move(sourceName)) {}

  // The root object with a known "type" and "version"; rejects fields outside `allowed`.
  void checkHeader(const Json& root, const std::string& expectedType,
                   std::initializer_list<const char*> allowed) const {
    if (!root.is_object())
      fail("", "expected a JSON object, got " + detail::describeJsonType(root));
    checkTypeAndVersion(root, expectedType, kSplineFormatVersion);
    rejectUnknownFields(root, allowed, expectedType);
  }

  int degree(const Json& object, const char* key) const {
    const int value = integer(object, key);
    if (value < 1 || value > kMaxSplineDegree) {
      fail(key, "degree " + std::to_string(value) + " is not supported (expected 1 to " +
                    std::to_string(kMaxSplineDegree) + ")");
    }
    return value;
  }

  KnotVector knots(const Json& object, const char* key, int degree) const {
    const Json& values = array(field(object, key, "an array of numbers"), key);
    std::vector<double> knots;
    for (std::size_t i = 0; i < values.size(); ++i) {
      knots.push_back(number(values[i], std::string(key) + "[" + std::to_string(i) + "]"));
    }
    try {
      return KnotVector(degree, std::move(knots));
    } catch (const InputError& error) {
      fail(key, error.what());
    }
  }

  // For a closed direction: the unique count implied by the knots must be at least degree + 1
  // and the knots must be uniform periodic.
  void checkPeriodic(const KnotVector& knots, const char* key, int uniqueCount) const {
    const int p = knots.degree();
    if (knots.size() != uniqueCount + 2 * p + 1) {
      fail(key, "a closed direction with " + std::to_string(uniqueCount) +
                    " unique control points of degree " + std::to_string(p) + " needs " +
                    std::to_string(uniqueCount + 2 * p + 1) +
                    " knots (control points + 2 degree + 1), got " + std::to_string(knots.size()));
    }
    if (uniqueCount < p + 1) {
      fail("control_points", "a closed direction of degree " + std::to_string(p) +
                                 " needs at least " + std::to_string(p + 1) +
                                 " unique control points, got " + std::to_string(uniqueCount));
    }
    if (!knots.isUniformPeriodic()) {
      fail(key,
           "the knots of a closed direction must be uniform periodic (equally spaced to within "
           "1e-9 of the domain length), but they are not");
    }
  }

  BSplineCurve curve(const Json& root) const {
    checkHeader(root, kCurveType,
                {"type", "version", "dimension", "degree", "closed", "knots", "control_points"});
    const int dimension = integer(root, "dimension");
    if (dimension != 2 && dimension != 3) {
      fail("dimension",
           "dimension " + std::to_string(dimension) + " is not supported (expected 2 or 3)");
    }
    const int p = degree(root, "degree");
    const bool closed = optionalBoolean(root, "closed");
    const KnotVector knotVector = knots(root, "knots", p);
    const Json& points =
        array(field(root, "control_points", "an array of points"), "control_points");
    std::vector<Eigen::Vector3d> controlPoints;
    for (std::size_t i = 0; i < points.size(); ++i) {
      controlPoints.push_back(
          point(points[i], "control_points[" + std::to_string(i) + "]", dimension));
    }
    const int count = static_cast<int>(controlPoints.size());
    if (closed) {
      checkPeriodic(knotVector, "knots", count);
    } else if (count != knotVector.basisFunctionCount()) {
      fail("control_points", "has " + std::to_string(count) + " points, but the " +
                                 std::to_string(knotVector.size()) + " knots of degree " +
                                 std::to_string(p) + " need " +
                                 std::to_string(knotVector.basisFunctionCount()) +
                                 " (knots = control points + degree + 1)");
    }
    try {
      return BSplineCurve(knotVector, std::move(controlPoints), dimension, closed);
    } catch (const InputError& error) {
      fail("", error.what());
    }
  }

  BSplineSurface surface(const Json& root) const {
    checkHeader(root, kSurfaceType,
                {"type", "version", "degree_u", "degree_v", "closed_u", "closed_v", "knots_u",
                 "knots_v", "control_points"});
    const int p = degree(root, "degree_u");
    const int q = degree(root, "degree_v");
    const bool closedU = optionalBoolean(root, "closed_u");
    const bool closedV = optionalBoolean(root, "closed_v");
    const KnotVector knotsU = knots(root, "knots_u", p);
    const KnotVector knotsV = knots(root, "knots_v", q);
    const int countU = closedU ? knotsU.basisFunctionCount() - p : knotsU.basisFunctionCount();
    const int countV = closedV ? knotsV.basisFunctionCount() - q : knotsV.basisFunctionCount();
    if (closedU) checkPeriodic(knotsU, "knots_u", countU);
    if (closedV) checkPeriodic(knotsV, "knots_v", countV);
    const Json& rows =
        array(field(root, "control_points", "an array of rows of points"), "control_points");
    if (rows.size() != static_cast<std::size_t>(countU)) {
      fail("control_points", "has " + std::to_string(rows.size()) + " rows, but knots_u (" +
                                 std::to_string(knotsU.size()) + " knots of degree " +
                                 std::to_string(p) + (closedU ? ", closed" : "") + ") needs " +
                                 std::to_string(countU));
    }
    std::vector<Eigen::Vector3d> controlPoints;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const std::string rowPath = "control_points[" + std::to_string(i) + "]";
      const Json& row = array(rows[i], rowPath);
      if (row.size() != static_cast<std::size_t>(countV)) {
        fail(rowPath, "has " + std::to_string(row.size()) + " points, but knots_v (" +
                          std::to_string(knotsV.size()) + " knots of degree " + std::to_string(q) +
                          (closedV ? ", closed" : "") + ") needs " + std::to_string(countV));
      }
      for (std::size_t j = 0; j < row.size(); ++j) {
        controlPoints.push_back(point(row[j], rowPath + "[" + std::to_string(j) + "]", 3));
      }
    }
    try {
      return BSplineSurface(knotsU, knotsV, std::move(controlPoints), closedU, closedV);
    } catch (const InputError& error) {
      fail("", error.what());
    }
  }

  Spline spline(const Json& root) const {
    if (!root.is_object())
      fail("", "expected a JSON object, got " + detail::describeJsonType(root));
    const std::string type = string(root, "type");
    if (type == kCurveType) return curve(root);
    if (type == kSurfaceType) return surface(root);
    fail("type",
         "is \"" + type + "\", expected \"" + kCurveType + "\" or \"" + kSurfaceType + "\"");
  }
};

std::string readText(const std::filesystem::path& file) {
  return detail::readTextFile(file, "spline file");
}

std::string pointText(const Eigen::Vector3d& point, int dimension) {
  std::string text = "[";
  for (int axis = 0; axis < dimension; ++axis) {
    text += (axis == 0 ? "" : ", ") + detail::jsonNumberText(point[axis]);
  }
  return text + "]";
}

std::string knotsText(const KnotVector& knots) {
  std::string text = "[";
  for (int i = 0; i < knots.size(); ++i)
    text += (i == 0 ? "" : ", ") + detail::jsonNumberText(knots[i]);
  return text + "]";
}

}  // namespace

BSplineCurve detail::curveFromJson(const Json& document, const std::string& sourceName) {
  return SplineReader(sourceName).curve(document);
}

BSplineSurface detail::surfaceFromJson(const Json& document, const std::string& sourceName) {
  return SplineReader(sourceName).surface(document);
}

BSplineCurve parseCurveJson(const std::string& text, const std::string& sourceName) {
  const SplineReader reader(sourceName);
  return reader.curve(reader.parse(text));
}

BSplineSurface parseSurfaceJson(const std::string& text, const std::string& sourceName) {
  const SplineReader reader(sourceName);
  return reader.surface(reader.parse(text));
}

Spline parseSplineJson(const std::string& text, const std::string& sourceName) {
  const SplineReader reader(sourceName);
  return reader.spline(reader.parse(text));
}

BSplineCurve readCurveJson(const std::filesystem::path& file) {
  return parseCurveJson(readText(file), file.string());
}

BSplineSurface readSurfaceJson(const std::filesystem::path& file) {
  return parseSurfaceJson(readText(file), file.string());
}

Spline readSplineJson(const std::filesystem::path& file) {
  return parseSplineJson(readText(file), file.string());
}

std::string curveToJson(const BSplineCurve& curve) {
  std::string text = "{\n";
  text += "  \"type\": \"" + std::string(kCurveType) + "\",\n";
  text += "  \"version\": " + std::to_string(kSplineFormatVersion) + ",\n";
  text += "  \"dimension\": " + std::to_string(curve.dimension()) + ",\n";
  text += "  \"degree\": " + std::to_string(curve.degree()) + ",\n";
  text += std::string("  \"closed\": ") + (curve.isClosed() ? "true" : "false") + ",\n";
  text += "  \"knots\": " + knotsText(curve.knots()) + ",\n";
  text += "  \"control_points\": [\n";
  const std::vector<Eigen::Vector3d>& points = curve.controlPoints();
  for (std::size_t i = 0; i < points.size(); ++i) {
    text +=
        "    " + pointText(points[i], curve.dimension()) + (i + 1 < points.size() ? ",\n" : "\n");
  }
  return text + "  ]\n}\n";
}

std::string surfaceToJson(const BSplineSurface& surface) {
  std::string text = "{\n";
  text += "  \"type\": \"" + std::string(kSurfaceType) + "\",\n";
  text += "  \"version\": " + std::to_string(kSplineFormatVersion) + ",\n";
  text += "  \"degree_u\": " + std::to_string(surface.degreeU()) + ",\n";
  text += "  \"degree_v\": " + std::to_string(surface.degreeV()) + ",\n";
  text += std::string("  \"closed_u\": ") + (surface.isClosedU() ? "true" : "false") + ",\n";
  text += std::string("  \"closed_v\": ") + (surface.isClosedV() ? "true" : "false") + ",\n";
  text += "  \"knots_u\": " + knotsText(surface.knotsU()) + ",\n";
  text += "  \"knots_v\": " + knotsText(surface.knotsV()) + ",\n";
  text += "  \"control_points\": [\n";
  for (int i = 0; i < surface.countU(); ++i) {
    text += "    [";
    for (int j = 0; j < surface.countV(); ++j) {
      text += (j == 0 ? "" : ", ") + pointText(surface.controlPoint(i, j), 3);
    }
    text += i + 1 < surface.countU() ? "],\n" : "]\n";
  }
  return text + "  ]\n}\n";
}

void writeCurveJson(const std::filesystem::path& file, const BSplineCurve& curve) {
  const std::string text = curveToJson(curve);
  writeStreamAtomically(file, [&](std::ostream& out) { out << text; });
}

void writeSurfaceJson(const std::filesystem::path& file, const BSplineSurface& surface) {
  const std::string text = surfaceToJson(surface);
  writeStreamAtomically(file, [&](std::ostream& out) { out << text; });
}

}  // namespace d2vdb
