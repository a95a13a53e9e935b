#include "d2vdb/io/PolylineFile.h"

#include <utility>

#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/io/detail/JsonDocuments.h"
#include "d2vdb/io/detail/JsonReader.h"
#include "d2vdb/io/detail/TextFile.h"

namespace d2vdb {
namespace {

using detail::elementPath;
using detail::Json;
using detail::memberPath;

constexpr int kPolylineFormatVersion = 1;
constexpr const char* kPolylineType = "polyline";
constexpr const char* kFileKind = "polyline file";

// Minimum point counts: a segment, or a triangle when closed.
std::size_t minimumPoints(bool closed) {
  return closed ? 3 : 2;
}

class PolylineReader : public detail::JsonFieldReader {
 public:
  explicit PolylineReader(std::string sourceName)
      : JsonFieldReader(kFileKind, std::move(sourceName)) {}

  std::vector<Polyline> polylines(const Json& root) const {
    object(root, "");
    // Slice files have no "type": they are recognised by their "polylines" list.
    if (!root.contains("type") && root.contains("polylines")) return slice(root);
    return {polyline(root)};
  }

 private:
  Polyline polyline(const Json& root) const {
    checkTypeAndVersion(root, kPolylineType, kPolylineFormatVersion);
    rejectUnknownFields(root, {"type", "version", "dimension", "closed", "points"}, kPolylineType);
    const int dimension = integer(root, "dimension");
    if (dimension != 2 && dimension != 3) {
      fail("dimension",
           "dimension " + std::to_string(dimension) + " is not supported (expected 2 or 3)");
    }
    Polyline result;
    result.dimension = dimension;
    result.closed = optionalBoolean(root, "closed");
    result.points =
        points(field(root, "points", "an array of points"), "points", dimension, result.closed);
    return result;
  }

  std::vector<Polyline> slice(const Json& root) const {
    rejectUnknownFields(root, {"axis", "offset", "iso", "plane_axes", "polylines"},
                        "slice polyline file");
    const std::string axis = string(root, "axis");
    if (axis != "x" && axis != "y" && axis != "z") {
      fail("axis", "is \"" + axis + "\", expected \"x\", \"y\" or \"z\"");
    }
    number(field(root, "offset", "a number"), "offset");
    number(field(root, "iso", "a number"), "iso");
    const Json& planeAxes = array(field(root, "plane_axes", "two axis names"), "plane_axes");
    if (planeAxes.size() != 2 || !planeAxes[0].is_string() || !planeAxes[1].is_string()) {
      fail("plane_axes", "expected two axis names such as [\"x\", \"y\"], got " + planeAxes.dump());
    }
    // The two axes spanning the slice plane: distinct axis names other than the slice's axis.
    for (std::size_t i = 0; i < 2; ++i) {
      const std::string name = planeAxes[i].get<std::string>();
      if ((name != "x" && name != "y" && name != "z") || name == axis ||
          (i == 1 && name == planeAxes[0].get<std::string>())) {
        fail(elementPath("plane_axes", i),
             "is " + planeAxes[i].dump() + "; the plane of a slice along \"" + axis +
                 "\" is spanned by the two other axes, each named once");
      }
    }
    const Json& lines = array(field(root, "polylines", "an array of polylines"), "polylines");
    std::vector<Polyline> result;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const std::string path = elementPath("polylines", i);
      const Json& line = object(lines[i], path);
      rejectUnknownFields(line, {"closed", "points"}, "slice polyline", path);
      Polyline polyline;
      polyline.dimension = 2;
      polyline.closed = boolean(line, "closed", path);
      polyline.points = points(field(line, "points", "an array of points", path),
                               memberPath(path, "points"), 2, polyline.closed);
      result.push_back(std::move(polyline));
    }
    return result;
  }

  std::vector<Eigen::Vector3d> points(const Json& value, const std::string& path, int dimension,
                                      bool closed) const {
    const Json& list = array(value, path);
    std::vector<Eigen::Vector3d> result;
    result.reserve(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) {
      result.push_back(point(list[i], elementPath(path, i), dimension));
    }
    if (result.size() < minimumPoints(closed)) {
      fail(path,
           "has " + std::to_string(result.size()) + " points; " +
               (closed ? "a closed polyline needs at least 3" : "a polyline needs at least 2"));
    }
    return result;
  }
};

}  // namespace

std::vector<Polyline> detail::polylinesFromJson(const Json& document,
                                                const std::string& sourceName) {
  return PolylineReader(sourceName).polylines(document);
}

std::vector<Polyline> parsePolylines(const std::string& text, const std::string& sourceName) {
  const PolylineReader reader(sourceName);
  return reader.polylines(reader.parse(text));
}

std::vector<Polyline> readPolylines(const std::filesystem::path& file) {
  return parsePolylines(detail::readTextFile(file, kFileKind), file.string());
}

Polyline readPolyline(const std::filesystem::path& file) {
  return onlyPolyline(readPolylines(file), file);
}

Polyline onlyPolyline(std::vector<Polyline> polylines, const std::filesystem::path& file) {
  if (polylines.size() != 1) {
    throw InputError(std::string(kFileKind) + " '" + file.string() + "' holds " +
                     std::to_string(polylines.size()) +
                     " polylines; exactly one is needed here (write each to its own file)");
  }
  return std::move(polylines.front());
}

std::string polylineToJson(const Polyline& polyline) {
  const int dimension = polyline.dimension;
  if (dimension != 2 && dimension != 3) {
    throw InputError("cannot write a polyline of dimension " + std::to_string(dimension) +
                     " (expected 2 or 3)");
  }
  if (polyline.points.size() < minimumPoints(polyline.closed)) {
    throw InputError("cannot write a " + std::string(polyline.closed ? "closed " : "") +
                     "polyline of " + std::to_string(polyline.points.size()) +
                     " points (needs at least " + std::to_string(minimumPoints(polyline.closed)) +
                     ")");
  }
  std::string text = "{\n";
  text += "  \"type\": \"" + std::string(kPolylineType) + "\",\n";
  text += "  \"version\": " + std::to_string(kPolylineFormatVersion) + ",\n";
  text += "  \"dimension\": " + std::to_string(dimension) + ",\n";
  text += std::string("  \"closed\": ") + (polyline.closed ? "true" : "false") + ",\n";
  text += "  \"points\": [\n";
  for (std::size_t i = 0; i < polyline.points.size(); ++i) {
    const Eigen::Vector3d& point = polyline.points[i];
    if (!point.allFinite()) {
      throw InputError("cannot write polyline point " + std::to_string(i) +
                       ": it has a non-finite coordinate");
    }
    if (dimension == 2 && point.z() != 0.0) {
      throw InputError("cannot write polyline point " + std::to_string(i) +
                       " of a 2D polyline: its z is " + detail::jsonNumberText(point.z()) +
                       ", not 0");
    }
    text += "    [";
    for (int axis = 0; axis < dimension; ++axis) {
      text += (axis == 0 ? "" : ", ") + detail::jsonNumberText(point[axis]);
    }
    text += i + 1 < polyline.points.size() ? "],\n" : "]\n";
  }
  return text + "  ]\n}\n";
}

void writePolyline(const std::filesystem::path& file, const Polyline& polyline) {
  const std::string text = polylineToJson(polyline);
  writeStreamAtomically(file, [&](std::ostream& out) { out << text; });
}

}  // namespace d2vdb
