// The STL reader (ASCII and binary, welded on read, every malformed byte reported with its
// offset) and writer.
#include "d2vdb/mesh/detail/StlFormat.h"

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <istream>
#include <ostream>
#include <unordered_map>

#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/detail/ByteOrder.h"
#include "d2vdb/mesh/detail/MeshFileCommon.h"
#include "d2vdb/mesh/detail/TextScanner.h"

namespace d2vdb::detail {
namespace {

using detail::ByteOrder;
using detail::inQuotes;
using detail::LineScanner;
using detail::NumberStatus;
using detail::throwAtByte;
using detail::throwAtLine;
using detail::throwInFile;
using detail::TokenReader;

constexpr std::size_t kBinaryHeaderSize = 80;
constexpr std::size_t kBinaryPreambleSize = 84;  // header + uint32 triangle count
constexpr std::size_t kBinaryFacetSize = 50;     // normal, 3 corners, uint16 attribute

bool equalsIgnoringCase(std::string_view text, std::string_view lowerCaseWord) {
  if (text.size() != lowerCaseWord.size()) return false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    const char lower = (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
    if (lower != lowerCaseWord[i]) return false;
  }
  return true;
}

bool startsWithSolid(std::string_view contents) {
  TokenReader tokens(detail::withoutByteOrderMark(contents).substr(0, 256));
  std::string_view first;
  return tokens.next(first) && equalsIgnoringCase(first, "solid");
}

/// Gives exactly equal positions one shared index, numbering vertices by first occurrence.
class VertexWelder {
 public:
  explicit VertexWelder(TriangleMesh& mesh) : mesh_(mesh) {}

  void reserve(std::size_t cornerCount) { indexOf_.reserve(cornerCount); }

  TriangleMesh::Index indexOf(const Eigen::Vector3f& position) {
    Key key;
    for (int axis = 0; axis < 3; ++axis) {
      const float value = position[axis] == 0.0f ? 0.0f : position[axis];  // -0 welds with +0
      std::memcpy(&key[static_cast<std::size_t>(axis)], &value, sizeof(float));
    }
    const auto [entry, inserted] =
        indexOf_.try_emplace(key, static_cast<TriangleMesh::Index>(mesh_.positions.size()));
    if (inserted) mesh_.positions.push_back(position);
    return entry->second;
  }

 private:
  using Key = std::array<std::uint32_t, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& key) const {
      std::uint64_t hash = 0x9E3779B97F4A7C15ull;
      for (const std::uint32_t bits : key) {
        hash ^= bits;
        hash *= 0xBF58476D1CE4E5B9ull;
        hash ^= hash >> 31;
      }
      return static_cast<std::size_t>(hash);
    }
  };

  TriangleMesh& mesh_;
  std::unordered_map<Key, TriangleMesh::Index, KeyHash> indexOf_;
};

TriangleMesh parseBinary(std::string_view contents, const std::string& fileName) {
  if (contents.size() < kBinaryPreambleSize) {
    throwInFile(fileName, "the file has " + std::to_string(contents.size()) +
                              " bytes: too short for a binary STL (84 bytes at least), and it "
                              "does not start with 'solid' as an ASCII STL does");
  }
  const auto triangleCount =
      detail::loadScalar<std::uint32_t>(contents.data() + kBinaryHeaderSize, ByteOrder::Little);
  const std::uint64_t expectedSize =
      kBinaryPreambleSize + std::uint64_t{kBinaryFacetSize} * triangleCount;
  if (expectedSize != contents.size()) {
    throwAtByte(fileName, kBinaryHeaderSize,
                "the binary STL header declares " + std::to_string(triangleCount) +
                    " triangles, which take " + std::to_string(expectedSize) +
                    " bytes, but the file has " + std::to_string(contents.size()) + " bytes" +
                    (contents.size() < expectedSize ? " (truncated file?)" : " (extra data)"));
  }
  if (triangleCount == 0) throwAtByte(fileName, kBinaryHeaderSize, "the STL file has no triangles");
  TriangleMesh mesh;
  VertexWelder welder(mesh);
  welder.reserve(std::size_t{3} * triangleCount);
  mesh.triangles.reserve(triangleCount);
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const std::size_t facetStart = kBinaryPreambleSize + kBinaryFacetSize * t;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const std::size_t offset = facetStart + 4 * axis;
      if (!std::isfinite(detail::loadScalar<float>(contents.data() + offset, ByteOrder::Little))) {
        throwAtByte(fileName, offset,
                    "the facet normal of triangle " + std::to_string(t) + " is not finite");
      }
    }
    TriangleMesh::Triangle triangle{};
    for (std::size_t corner = 0; corner < 3; ++corner) {
      Eigen::Vector3f position;
      for (std::size_t axis = 0; axis < 3; ++axis) {
        const std::size_t offset = facetStart + 12 + 12 * corner + 4 * axis;
        const float value = detail::loadScalar<float>(contents.data() + offset, ByteOrder::Little);
        if (!std::isfinite(value)) {
          throwAtByte(fileName, offset,
                      "a vertex coordinate of triangle " + std::to_string(t) + " is not finite");
        }
        position[static_cast<int>(axis)] = value;
      }
      triangle[corner] = welder.indexOf(position);
    }
    mesh.triangles.push_back(triangle);
  }
  return mesh;
}

/// Tokens of an ASCII STL, read across line breaks, remembering the line of the last one.
class StlTokens {
 public:
  explicit StlTokens(std::string_view contents) : lines_(detail::withoutByteOrderMark(contents)) {}

  bool next(std::string_view& token) {
    while (!tokens_.next(token)) {
      std::string_view line;
      if (!lines_.next(line)) return false;
      tokens_ = TokenReader(line);
    }
    return true;
  }

  /// Drops the rest of the current line (a solid's name).
  void skipRestOfLine() { tokens_ = TokenReader(std::string_view()); }

  std::size_t lineNumber() const { return lines_.lineNumber(); }

 private:
  LineScanner lines_;
  TokenReader tokens_{std::string_view()};
};

class AsciiStlParser {
 public:
  AsciiStlParser(std::string_view contents, const std::string& fileName)
      : tokens_(contents), fileName_(fileName), welder_(mesh_) {}

  TriangleMesh parse() {
    std::string_view token;
    while (tokens_.next(token)) {
      if (!equalsIgnoringCase(token, "solid")) {
        fail("expected 'solid', found " + inQuotes(token));
      }
      tokens_.skipRestOfLine();
      parseSolid();
    }
    if (mesh_.triangles.empty()) fail("the STL file has no facets");
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throwAtLine(fileName_, tokens_.lineNumber(), problem);
  }

  std::string_view nextToken(const char* expected) {
    std::string_view token;
    if (!tokens_.next(token)) {
      fail(std::string("the file ends where ") + expected +
           " was expected (truncated file? an ASCII STL ends with 'endsolid')");
    }
    return token;
  }

  void expectKeyword(std::string_view lowerCaseWord) {
    std::string_view token;
    const bool found = tokens_.next(token);
    if (found && equalsIgnoringCase(token, lowerCaseWord)) return;
    const std::string expected = "'" + std::string(lowerCaseWord) + "'";
    if (!found) nextToken(expected.c_str());  // throws the end-of-file message
    fail("expected " + expected + ", found " + inQuotes(token));
  }

  void parseSolid() {
    while (true) {
      const std::string_view token = nextToken("'facet' or 'endsolid'");
      if (equalsIgnoringCase(token, "endsolid")) {
        tokens_.skipRestOfLine();
        return;
      }
      if (!equalsIgnoringCase(token, "facet")) {
        fail("expected 'facet' or 'endsolid', found " + inQuotes(token));
      }
      parseFacet();
    }
  }

  void parseFacet() {
    expectKeyword("normal");
    for (int axis = 0; axis < 3; ++axis) {
      // Facet normals are recomputed from the corners when needed, but like every number of a
      // mesh file they must be finite: a NaN or infinite normal marks a broken export.
      const std::string_view token = nextToken("a facet normal component");
      detail::parseFiniteFloat(token, fileName_, tokens_.lineNumber(), "facet normal component");
    }
    expectKeyword("outer");
    expectKeyword("loop");
    TriangleMesh::Triangle triangle{};
    for (std::size_t corner = 0; corner < 3; ++corner) {
      const std::string_view token = nextToken("'vertex'");
      if (!equalsIgnoringCase(token, "vertex")) {
        if (equalsIgnoringCase(token, "endloop")) {
          fail("facet has " + std::to_string(corner) + " vertices, 3 are needed");
        }
        fail("expected 'vertex', found " + inQuotes(token));
      }
      Eigen::Vector3f position;
      static constexpr std::array<const char*, 3> kNames = {
          "vertex x coordinate", "vertex y coordinate", "vertex z coordinate"};
      for (int axis = 0; axis < 3; ++axis) {
        const char* const name = kNames[static_cast<std::size_t>(axis)];
        const std::string_view value = nextToken(name);
        position[axis] = detail::parseFiniteFloat(value, fileName_, tokens_.lineNumber(), name);
      }
      triangle[corner] = welder_.indexOf(position);
    }
    const std::string_view token = nextToken("'endloop'");
    if (equalsIgnoringCase(token, "vertex")) fail("facet has more than 3 vertices");
    if (!equalsIgnoringCase(token, "endloop")) fail("expected 'endloop', found " + inQuotes(token));
    expectKeyword("endfacet");
    mesh_.triangles.push_back(triangle);
  }

  StlTokens tokens_;
  const std::string& fileName_;
  TriangleMesh mesh_;
  VertexWelder welder_;
};

/// Unit normal of a triangle by the right-hand rule (computed in double), zero if degenerate.
Eigen::Vector3f facetNormal(const TriangleMesh& mesh, const TriangleMesh::Triangle& triangle) {
  const Eigen::Vector3d a = mesh.positions[triangle[0]].cast<double>();
  const Eigen::Vector3d b = mesh.positions[triangle[1]].cast<double>();
  const Eigen::Vector3d c = mesh.positions[triangle[2]].cast<double>();
  const Eigen::Vector3d cross = (b - a).cross(c - a);
  const double length = cross.norm();
  if (!(length > 0.0) || !std::isfinite(length)) return Eigen::Vector3f::Zero();
  return (cross / length).cast<float>();
}

void writeBinary(std::ostream& out, const TriangleMesh& mesh) {
  std::string buffer = "binary STL written by d2vdb";
  buffer.resize(kBinaryHeaderSize, '\0');
  detail::appendScalar(buffer, static_cast<std::uint32_t>(mesh.triangles.size()),
                       ByteOrder::Little);
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    const Eigen::Vector3f normal = facetNormal(mesh, triangle);
    for (int axis = 0; axis < 3; ++axis) {
      detail::appendScalar(buffer, normal[axis], ByteOrder::Little);
    }
    for (const TriangleMesh::Index index : triangle) {
      for (int axis = 0; axis < 3; ++axis) {
        detail::appendScalar(buffer, mesh.positions[index][axis], ByteOrder::Little);
      }
    }
    detail::appendScalar(buffer, std::uint16_t{0}, ByteOrder::Little);
    detail::flushBuffer(buffer, out);
  }
  detail::flushBuffer(buffer, out, true);
}

void writeAscii(std::ostream& out, const TriangleMesh& mesh) {
  std::string buffer = "solid d2vdb\n";
  const auto appendVector = [&buffer](const Eigen::Vector3f& vector) {
    for (int axis = 0; axis < 3; ++axis) {
      buffer += ' ';
      detail::appendFloat(buffer, vector[axis]);
    }
    buffer += '\n';
  };
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    buffer += "  facet normal";
    appendVector(facetNormal(mesh, triangle));
    buffer += "    outer loop\n";
    for (const TriangleMesh::Index index : triangle) {
      buffer += "      vertex";
      appendVector(mesh.positions[index]);
    }
    buffer += "    endloop\n  endfacet\n";
    detail::flushBuffer(buffer, out);
  }
  buffer += "endsolid d2vdb\n";
  detail::flushBuffer(buffer, out, true);
}

}  // namespace

StlEncoding detectStlEncoding(std::string_view contents) {
  if (contents.size() >= kBinaryPreambleSize) {
    const auto triangleCount =
        detail::loadScalar<std::uint32_t>(contents.data() + kBinaryHeaderSize, ByteOrder::Little);
    if (kBinaryPreambleSize + std::uint64_t{kBinaryFacetSize} * triangleCount == contents.size()) {
      return StlEncoding::Binary;
    }
  }
  const bool hasNul = std::memchr(contents.data(), '\0', contents.size()) != nullptr;
  if (startsWithSolid(contents) && !hasNul) return StlEncoding::Ascii;
  return StlEncoding::Binary;
}

TriangleMesh parseStl(std::string_view contents, const std::string& nameForMessages) {
  if (contents.empty()) throwInFile(nameForMessages, "the file is empty");
  if (detectStlEncoding(contents) == StlEncoding::Ascii) {
    return AsciiStlParser(contents, nameForMessages).parse();
  }
  return parseBinary(contents, nameForMessages);
}

TriangleMesh readStl(std::istream& in, const std::string& nameForMessages) {
  const std::string contents = detail::readStreamContents(in, nameForMessages);
  return parseStl(contents, nameForMessages);
}

void writeStl(std::ostream& out, const TriangleMesh& mesh, StlEncoding encoding) {
  detail::checkMeshIsWritable(mesh, "STL");
  if (mesh.triangles.empty()) {
    throw InputError("cannot write the mesh as STL: it has no triangles (STL stores only facets)");
  }
  if (encoding == StlEncoding::Binary) {
    if (mesh.triangles.size() > 0xFFFFFFFFull) {
      throw InputError("cannot write the mesh as binary STL: more than 2^32-1 triangles");
    }
    writeBinary(out, mesh);
  } else {
    writeAscii(out, mesh);
  }
}

}  // namespace d2vdb::detail
