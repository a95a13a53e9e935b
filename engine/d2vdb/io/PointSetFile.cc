#include "d2vdb/io/PointSetFile.h"

#include <array>
#include <charconv>
#include <cmath>
#include <system_error>

#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/detail/FileExtension.h"
#include "d2vdb/io/detail/TextFile.h"
#include "d2vdb/mesh/MeshIO.h"

namespace d2vdb {
namespace {

// A blank that separates numbers within one line (the line breaks are gone already).
bool isBlankWithinLine(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

[[noreturn]] void failAtLine(const std::string& source, std::size_t line,
                             const std::string& problem) {
  throw InputError("point file '" + source + "', line " + std::to_string(line) + ": " + problem);
}

// `token` for a message: quoted, at most 40 characters.
std::string quoted(std::string_view token) {
  return "'" + std::string(token.substr(0, 40)) + (token.size() > 40 ? "...'" : "'");
}

// Parses one whole token as a finite double or fails naming the line and the coordinate.
double parseCoordinate(std::string_view token, const std::string& source, std::size_t line,
                       const char* axis) {
  std::string_view digits = token;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error == std::errc::result_out_of_range) {
    failAtLine(source, line,
               std::string(axis) + " coordinate " + quoted(token) + " is out of double range");
  }
  if (error != std::errc() || end != digits.data() + digits.size() || digits.empty()) {
    failAtLine(source, line,
               std::string(axis) + " coordinate " + quoted(token) + " is not a number");
  }
  if (!std::isfinite(value)) {
    failAtLine(source, line,
               std::string(axis) + " coordinate " + quoted(token) + " is not a finite number");
  }
  return value;
}

void checkWritable(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) throw InputError("cannot write an empty point set");
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      throw InputError("cannot write point " + std::to_string(i) +
                       " of the point set: it has a non-finite coordinate");
    }
  }
}

}  // namespace

std::vector<Eigen::Vector3d> parseXyz(std::string_view text, const std::string& sourceName) {
  static constexpr const char* kAxes[3] = {"x", "y", "z"};
  std::vector<Eigen::Vector3d> points;
  std::size_t lineNumber = 0;
  while (!text.empty()) {
    ++lineNumber;
    const std::size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    line = line.substr(0, line.find('#'));
    std::string_view tokens[3];
    int count = 0;
    while (count < 3) {
      while (!line.empty() && isBlankWithinLine(line.front())) line.remove_prefix(1);
      if (line.empty()) break;
      std::size_t stop = 0;
      while (stop < line.size() && !isBlankWithinLine(line[stop])) ++stop;
      tokens[count++] = line.substr(0, stop);
      line.remove_prefix(stop);
    }
    if (count == 0) continue;  // blank or comment line
    if (count < 3) {
      failAtLine(sourceName, lineNumber,
                 "expected three coordinates 'x y z', found " + std::to_string(count) +
                     (count == 1 ? " value" : " values") + " (truncated line?)");
    }
    Eigen::Vector3d point;
    for (int axis = 0; axis < 3; ++axis) {
      point[axis] = parseCoordinate(tokens[axis], sourceName, lineNumber, kAxes[axis]);
    }
    points.push_back(point);
  }
  if (points.empty()) {
    throw InputError("point file '" + sourceName +
                     "' contains no points (only blank or comment lines)");
  }
  return points;
}

std::vector<Eigen::Vector3d> readPointSet(const std::filesystem::path& file) {
  const std::string extension = detail::lowerExtension(file);
  if (extension == ".xyz") return parseXyz(detail::readTextFile(file, "point file"), file.string());
  if (extension == ".ply") {
    // The mesh reader is strict (line / byte positions) and rejects a file without vertices.
    const TriangleMesh mesh = readMesh(file);
    std::vector<Eigen::Vector3d> points;
    points.reserve(mesh.positions.size());
    for (const Eigen::Vector3f& position : mesh.positions)
      points.push_back(position.cast<double>());
    return points;
  }
  throw InputError("point file '" + file.string() + "' has the extension '" + extension +
                   "'; point sets are read from .xyz and .ply files");
}

std::string pointSetToXyz(const std::vector<Eigen::Vector3d>& points) {
  checkWritable(points);
  std::string text;
  text.reserve(points.size() * 72);
  std::array<char, 40> buffer{};
  for (const Eigen::Vector3d& point : points) {
    for (int axis = 0; axis < 3; ++axis) {
      // 17 significant digits, locale-independent: reads back as exactly the same double.
      const std::to_chars_result result =
          std::to_chars(buffer.data(), buffer.data() + buffer.size(), point[axis],
                        std::chars_format::general, 17);
      text.append(buffer.data(), result.ptr);
      text += axis < 2 ? ' ' : '\n';
    }
  }
  return text;
}

void writePointSet(const std::filesystem::path& file, const std::vector<Eigen::Vector3d>& points) {
  if (detail::lowerExtension(file) != ".xyz") {
    throw InputError("cannot write point file '" + file.string() +
                     "': point sets are written as .xyz files");
  }
  const std::string text = pointSetToXyz(points);
  writeStreamAtomically(file, [&](std::ostream& out) { out << text; });
}

}  // namespace d2vdb
