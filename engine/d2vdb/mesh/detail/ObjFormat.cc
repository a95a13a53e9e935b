// The OBJ reader (v, vn, f with polygon fans, errors with line numbers) and writer.
#include "d2vdb/mesh/detail/ObjFormat.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <istream>
#include <ostream>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/detail/MeshFileCommon.h"
#include "d2vdb/mesh/detail/TextScanner.h"

namespace d2vdb::detail {
namespace {

using detail::inQuotes;
using detail::kMaxVertexCount;
using detail::LineScanner;
using detail::NumberStatus;
using detail::parseFiniteFloat;
using detail::throwAtLine;
using detail::throwInFile;
using detail::TokenReader;

constexpr std::uint32_t kNoNormal = 0xFFFFFFFFu;

/// Statements that carry nothing a triangle mesh keeps (texture coordinates, grouping, materials,
/// display attributes, line and point elements).
bool isIgnoredStatement(std::string_view keyword) {
  static constexpr std::array<std::string_view, 22> kIgnored = {
      "vt",         "vp",        "g",      "o",      "s",    "usemtl", "mtllib",   "l",
      "p",          "mg",        "maplib", "usemap", "lod",  "bevel",  "c_interp", "d_interp",
      "shadow_obj", "trace_obj", "ctech",  "stech",  "call", "csh"};
  return std::find(kIgnored.begin(), kIgnored.end(), keyword) != kIgnored.end();
}

/// Statements of OBJ free-form geometry, which d2vdb does not tessellate.
bool isFreeFormStatement(std::string_view keyword) {
  static constexpr std::array<std::string_view, 14> kFreeForm = {
      "cstype", "deg",  "bmat", "step", "curv", "curv2", "surf",
      "parm",   "trim", "hole", "scrv", "sp",   "end",   "con"};
  return std::find(kFreeForm.begin(), kFreeForm.end(), keyword) != kFreeForm.end();
}

/// Turns OBJ indices of one kind (vertex, texture coordinate or normal) into 0-based indices.
/// Indices to elements defined later in the file are allowed; the largest is checked at the end.
class IndexResolver {
 public:
  explicit IndexResolver(const char* kind) : kind_(kind) {}

  /// The 0-based index `token` denotes when `definedSoFar` elements of this kind precede it.
  std::uint64_t resolve(std::string_view token, std::uint64_t definedSoFar,
                        const std::string& fileName, std::size_t lineNumber) {
    std::int64_t index = 0;
    const NumberStatus status = detail::parseInteger(token, index);
    if (status == NumberStatus::NotANumber) {
      throwAtLine(fileName, lineNumber, inQuotes(token) + " is not a valid " + kind_ + " index");
    }
    const auto limit = static_cast<std::int64_t>(kMaxVertexCount);
    if (status == NumberStatus::OutOfRange || index > limit || index < -limit) {
      throwAtLine(fileName, lineNumber,
                  std::string(kind_) + " index " + inQuotes(token) + " is out of range");
    }
    if (index == 0) {
      throwAtLine(fileName, lineNumber,
                  std::string(kind_) + " index 0 is invalid (OBJ indices start at 1)");
    }
    if (index < 0) {
      const auto back = static_cast<std::uint64_t>(-index);
      if (back > definedSoFar) {
        throwAtLine(fileName, lineNumber,
                    "relative " + std::string(kind_) + " index " + std::to_string(index) +
                        " refers before the first " + kind_ + " (only " +
                        std::to_string(definedSoFar) + " defined so far)");
      }
      return definedSoFar - back;
    }
    const auto oneBased = static_cast<std::uint64_t>(index);
    if (oneBased > definedSoFar && oneBased > largestForward_) {
      largestForward_ = oneBased;
      largestForwardLine_ = lineNumber;
    }
    return oneBased - 1;
  }

  /// Throws InputError when an index read earlier exceeds the final count of its kind.
  void checkAgainstTotal(std::uint64_t total, const std::string& fileName) const {
    if (largestForward_ > total) {
      throwAtLine(fileName, largestForwardLine_,
                  std::string(kind_) + " index " + std::to_string(largestForward_) +
                      " is out of range (the file defines " + std::to_string(total) + " " +
                      (total == 1 ? std::string(kind_) : plural()) + ")");
    }
  }

 private:
  // "vertices", "normals", "texture coordinates".
  std::string plural() const {
    const std::string kind = kind_;
    return kind == "vertex" ? "vertices" : kind + "s";
  }

  const char* kind_;
  std::uint64_t largestForward_ = 0;
  std::size_t largestForwardLine_ = 0;
};

/// Reads OBJ text statement by statement into a TriangleMesh.
class ObjParser {
 public:
  ObjParser(std::string_view text, const std::string& fileName)
      : text_(text), fileName_(fileName) {}

  TriangleMesh parse() {
    if (text_.empty()) throwInFile(fileName_, "the file is empty");
    LineScanner lines(detail::withoutByteOrderMark(text_));
    std::string_view line;
    while (lines.next(line)) parseStatement(line, lines.lineNumber());
    if (mesh_.positions.empty()) {
      throwInFile(fileName_, "no vertices ('v' statements) found: not an OBJ mesh");
    }
    vertices_.checkAgainstTotal(mesh_.positions.size(), fileName_);
    textureCoordinates_.checkAgainstTotal(textureCoordinateCount_, fileName_);
    normalIndices_.checkAgainstTotal(fileNormals_.size(), fileName_);
    // Every vertex now exists; the order corners are compared in does not change the outcome.
    for (const Corner& corner : forwardCorners_) recordCornerNormal(corner);
    assignNormals();
    return std::move(mesh_);
  }

 private:
  void parseStatement(std::string_view line, std::size_t lineNumber) {
    if (const void* hash = std::memchr(line.data(), '#', line.size())) {
      line = line.substr(0, static_cast<std::size_t>(static_cast<const char*>(hash) - line.data()));
    }
    TokenReader tokens(line);
    std::string_view keyword;
    if (!tokens.next(keyword)) return;
    if (keyword == "v") {
      if (mesh_.positions.size() >= kMaxVertexCount) {
        throwAtLine(fileName_, lineNumber, "too many vertices for 32-bit indices");
      }
      mesh_.positions.push_back(parseVector(tokens, lineNumber, VectorKind::Vertex));
      checkExtraNumbers(tokens, lineNumber);
    } else if (keyword == "vn") {
      fileNormals_.push_back(parseVector(tokens, lineNumber, VectorKind::Normal));
      checkExtraNumbers(tokens, lineNumber);
    } else if (keyword == "vt") {
      ++textureCoordinateCount_;
    } else if (keyword == "f" || keyword == "fo") {
      parseFace(tokens, lineNumber);
    } else if (isIgnoredStatement(keyword)) {
      return;
    } else if (isFreeFormStatement(keyword)) {
      throwAtLine(fileName_, lineNumber,
                  "free-form geometry (" + inQuotes(keyword) + ") is not supported");
    } else {
      throwAtLine(fileName_, lineNumber, "unknown OBJ statement " + inQuotes(keyword));
    }
  }

  /// What a parsed vector is, for messages.
  enum class VectorKind { Vertex, Normal };

  Eigen::Vector3f parseVector(TokenReader& tokens, std::size_t lineNumber, VectorKind kind) {
    static constexpr std::array<std::array<const char*, 3>, 2> kNames = {
        {{"vertex x coordinate", "vertex y coordinate", "vertex z coordinate"},
         {"normal x component", "normal y component", "normal z component"}}};
    const std::array<const char*, 3>& names = kNames[kind == VectorKind::Vertex ? 0 : 1];
    Eigen::Vector3f vector;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      std::string_view token;
      if (!tokens.next(token)) {
        throwAtLine(fileName_, lineNumber,
                    std::string(kind == VectorKind::Vertex ? "vertex" : "normal") + " has " +
                        std::to_string(axis) + " coordinates, 3 are needed");
      }
      vector[static_cast<int>(axis)] = parseFiniteFloat(token, fileName_, lineNumber, names[axis]);
    }
    return vector;
  }

  /// Whatever follows x y z (a weight, vertex colours) must still be numbers.
  void checkExtraNumbers(TokenReader& tokens, std::size_t lineNumber) const {
    std::string_view token;
    while (tokens.next(token)) {
      double ignored = 0.0;
      if (detail::parseDouble(token, ignored) == NumberStatus::NotANumber) {
        throwAtLine(fileName_, lineNumber, inQuotes(token) + " is not a number");
      }
    }
  }

  void parseFace(TokenReader& tokens, std::size_t lineNumber) {
    corners_.clear();
    std::string_view token;
    while (tokens.next(token)) corners_.push_back(parseCorner(token, lineNumber));
    if (corners_.size() < 3) {
      throwAtLine(fileName_, lineNumber,
                  "face has " + std::to_string(corners_.size()) +
                      (corners_.size() == 1 ? " corner" : " corners") + ", at least 3 are needed");
    }
    for (std::size_t i = 1; i + 1 < corners_.size(); ++i) {
      mesh_.triangles.push_back({corners_[0].vertex, corners_[i].vertex, corners_[i + 1].vertex});
    }
    for (const Corner& corner : corners_) recordCornerNormal(corner);
  }

  struct Corner {
    TriangleMesh::Index vertex = 0;
    std::uint32_t normal = kNoNormal;
  };

  Corner parseCorner(std::string_view token, std::size_t lineNumber) {
    std::array<std::string_view, 3> parts;
    std::size_t partCount = 0;
    std::string_view rest = token;
    while (true) {
      if (partCount == parts.size()) {
        throwAtLine(fileName_, lineNumber, "malformed face corner " + inQuotes(token));
      }
      const std::size_t slash = rest.find('/');
      parts[partCount++] = rest.substr(0, slash);
      if (slash == std::string_view::npos) break;
      rest.remove_prefix(slash + 1);
    }
    const bool malformed = parts[0].empty() || (partCount == 2 && parts[1].empty()) ||
                           (partCount == 3 && parts[2].empty());
    if (malformed) throwAtLine(fileName_, lineNumber, "malformed face corner " + inQuotes(token));

    Corner corner;
    corner.vertex = static_cast<TriangleMesh::Index>(
        vertices_.resolve(parts[0], mesh_.positions.size(), fileName_, lineNumber));
    if (partCount >= 2 && !parts[1].empty()) {
      textureCoordinates_.resolve(parts[1], textureCoordinateCount_, fileName_, lineNumber);
    }
    if (partCount == 3) {
      corner.normal = static_cast<std::uint32_t>(
          normalIndices_.resolve(parts[2], fileNormals_.size(), fileName_, lineNumber));
    }
    return corner;
  }

  /// Tracks whether every vertex is given one normal by all its face corners.
  void recordCornerNormal(const Corner& corner) {
    if (!normalsConsistent_) return;
    if (corner.normal == kNoNormal) {
      normalsConsistent_ = false;
      return;
    }
    if (corner.vertex >= mesh_.positions.size()) {
      // A vertex defined further down (or never: checkAgainstTotal refuses that at the end).
      // Sizing the table by such an index would let a few bytes allocate gigabytes.
      forwardCorners_.push_back(corner);
      return;
    }
    if (corner.vertex >= normalOfVertex_.size()) {
      normalOfVertex_.resize(mesh_.positions.size(), kNoNormal);
    }
    std::uint32_t& assigned = normalOfVertex_[corner.vertex];
    if (assigned == kNoNormal || assigned == corner.normal) {
      assigned = corner.normal;
      return;
    }
    // Different normal indices are still consistent when they hold the same vector.
    const bool bothKnown = assigned < fileNormals_.size() && corner.normal < fileNormals_.size();
    if (!bothKnown || fileNormals_[assigned] != fileNormals_[corner.normal]) {
      normalsConsistent_ = false;
    }
  }

  void assignNormals() {
    if (!normalsConsistent_ || fileNormals_.empty()) return;
    normalOfVertex_.resize(mesh_.positions.size(), kNoNormal);
    std::vector<Eigen::Vector3f> normals(mesh_.positions.size());
    for (std::size_t v = 0; v < normals.size(); ++v) {
      const std::size_t source = normalOfVertex_[v] != kNoNormal ? normalOfVertex_[v] : v;
      if (source >= fileNormals_.size()) return;  // an unused vertex without a normal
      normals[v] = fileNormals_[source];
    }
    mesh_.normals = std::move(normals);
  }

  std::string_view text_;
  const std::string& fileName_;
  TriangleMesh mesh_;
  std::vector<Eigen::Vector3f> fileNormals_;
  std::uint64_t textureCoordinateCount_ = 0;
  IndexResolver vertices_{"vertex"};
  IndexResolver textureCoordinates_{"texture coordinate"};
  IndexResolver normalIndices_{"normal"};
  std::vector<Corner> corners_;
  std::vector<std::uint32_t> normalOfVertex_;
  std::vector<Corner> forwardCorners_;  // corners naming a vertex not yet defined when read
  bool normalsConsistent_ = true;
};

}  // namespace

TriangleMesh parseObj(std::string_view text, const std::string& nameForMessages) {
  return ObjParser(text, nameForMessages).parse();
}

TriangleMesh readObj(std::istream& in, const std::string& nameForMessages) {
  const std::string contents = detail::readStreamContents(in, nameForMessages);
  return parseObj(contents, nameForMessages);
}

void writeObj(std::ostream& out, const TriangleMesh& mesh, const VertexAttributes* attributes) {
  detail::checkMeshIsWritable(mesh, "OBJ");
  if (attributes != nullptr) detail::checkVertexAttributes(mesh, *attributes);
  const bool withColors = attributes != nullptr && !attributes->colors.empty();
  const bool withNormals = mesh.hasNormals();
  std::string buffer;
  buffer += "# OBJ written by d2vdb: ";
  detail::appendUnsigned(buffer, mesh.positions.size());
  buffer += " vertices, ";
  detail::appendUnsigned(buffer, mesh.triangles.size());
  buffer += " triangles\n";
  const auto appendVector = [&buffer](const char* keyword, const Eigen::Vector3f& vector) {
    buffer += keyword;
    for (int axis = 0; axis < 3; ++axis) {
      buffer += ' ';
      detail::appendFloat(buffer, vector[axis]);
    }
    buffer += '\n';
  };
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    appendVector("v", mesh.positions[v]);
    if (withColors) {  // "v x y z r g b", channels in [0, 1]
      buffer.pop_back();
      for (const std::uint8_t channel : attributes->colors[v]) {
        buffer += ' ';
        detail::appendFloat(buffer, static_cast<float>(channel) / 255.0f);
      }
      buffer += '\n';
    }
    detail::flushBuffer(buffer, out);
  }
  if (withNormals) {
    for (const Eigen::Vector3f& normal : mesh.normals) {
      appendVector("vn", normal);
      detail::flushBuffer(buffer, out);
    }
  }
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    buffer += 'f';
    for (const TriangleMesh::Index index : triangle) {
      buffer += ' ';
      detail::appendUnsigned(buffer, std::uint64_t{index} + 1);
      if (withNormals) {
        buffer += "//";
        detail::appendUnsigned(buffer, std::uint64_t{index} + 1);
      }
    }
    buffer += '\n';
    detail::flushBuffer(buffer, out);
  }
  detail::flushBuffer(buffer, out, true);
}

}  // namespace d2vdb::detail
