// The PLY reader for the ascii and both binary encodings (header, element and property checks,
// vertex attributes) and writer.
#include "d2vdb/mesh/detail/PlyFormat.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <istream>
#include <limits>
#include <optional>
#include <ostream>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/detail/ByteOrder.h"
#include "d2vdb/mesh/detail/MeshFileCommon.h"
#include "d2vdb/mesh/detail/TextScanner.h"

namespace d2vdb::detail {
namespace {

using detail::ByteOrder;
using detail::inQuotes;
using detail::kMaxVertexCount;
using detail::LineScanner;
using detail::loadScalar;
using detail::NumberStatus;
using detail::throwAtByte;
using detail::throwAtLine;
using detail::throwInFile;
using detail::TokenReader;

// ---------------------------------------------------------------------------------------------
// Scalar types

enum class ScalarType : std::uint8_t {
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Float32,
  Float64
};

struct ScalarTypeInfo {
  std::string_view name;   ///< the original PLY name
  std::string_view alias;  ///< the sized alias
  std::size_t size;        ///< bytes in binary files
  bool integer;
  std::int64_t min;  ///< integer types: smallest value
  std::int64_t max;  ///< integer types: largest value
};

constexpr std::array<ScalarTypeInfo, 8> kScalarTypes = {{
    {"char", "int8", 1, true, -128, 127},
    {"uchar", "uint8", 1, true, 0, 255},
    {"short", "int16", 2, true, -32768, 32767},
    {"ushort", "uint16", 2, true, 0, 65535},
    {"int", "int32", 4, true, -2147483648LL, 2147483647LL},
    {"uint", "uint32", 4, true, 0, 4294967295LL},
    {"float", "float32", 4, false, 0, 0},
    {"double", "float64", 8, false, 0, 0},
}};

const ScalarTypeInfo& infoOf(ScalarType type) {
  return kScalarTypes[static_cast<std::size_t>(type)];
}

std::optional<ScalarType> scalarTypeNamed(std::string_view name) {
  for (std::size_t i = 0; i < kScalarTypes.size(); ++i) {
    if (kScalarTypes[i].name == name || kScalarTypes[i].alias == name) {
      return static_cast<ScalarType>(i);
    }
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------
// Header

/// What a property means to the reader.
enum class Role : std::uint8_t { Skip, X, Y, Z, NormalX, NormalY, NormalZ, VertexIndices };

struct PlyProperty {
  std::string name;
  bool isList = false;
  ScalarType countType = ScalarType::UInt8;  ///< lists only
  ScalarType valueType = ScalarType::Float32;
  Role role = Role::Skip;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t headerLine = 0;
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
  std::size_t bodyOffset = 0;     ///< byte offset of the first byte after end_header's line
  std::size_t bodyFirstLine = 0;  ///< line number of the body's first line (ASCII)
  bool hasNormals = false;
};

std::optional<PlyEncoding> encodingNamed(std::string_view name) {
  if (name == "ascii") return PlyEncoding::Ascii;
  if (name == "binary_little_endian") return PlyEncoding::BinaryLittleEndian;
  if (name == "binary_big_endian") return PlyEncoding::BinaryBigEndian;
  return std::nullopt;
}

class HeaderParser {
 public:
  HeaderParser(std::string_view contents, const std::string& fileName)
      : contents_(contents), fileName_(fileName), lines_(contents) {}

  PlyHeader parse() {
    if (contents_.empty()) throwInFile(fileName_, "the file is empty");
    std::string_view line;
    lines_.next(line);
    if (!isExactly(line, {"ply"})) {
      throwAtLine(fileName_, 1, "the file does not start with the line 'ply': not a PLY file");
    }
    bool formatSeen = false;
    while (true) {
      if (!lines_.next(line)) {
        throwAtLine(fileName_, lines_.lineNumber(),
                    "the header ends without 'end_header' (truncated file?)");
      }
      const std::size_t lineNumber = lines_.lineNumber();
      TokenReader tokens(line);
      std::string_view keyword;
      if (!tokens.next(keyword)) continue;
      if (keyword == "comment" || keyword == "obj_info") continue;
      if (keyword == "end_header") {
        expectNoMore(tokens, lineNumber);
        if (!formatSeen) throwAtLine(fileName_, lineNumber, "the header has no 'format' line");
        break;
      }
      if (keyword == "format") {
        if (formatSeen) throwAtLine(fileName_, lineNumber, "a second 'format' line");
        parseFormat(tokens, lineNumber);
        formatSeen = true;
      } else if (keyword == "element") {
        if (!formatSeen) {
          throwAtLine(fileName_, lineNumber, "'element' before the 'format' line");
        }
        parseElement(tokens, lineNumber);
      } else if (keyword == "property") {
        if (header_.elements.empty()) {
          throwAtLine(fileName_, lineNumber, "'property' before any 'element'");
        }
        parseProperty(tokens, lineNumber);
      } else {
        throwAtLine(fileName_, lineNumber, "unknown header keyword " + inQuotes(keyword));
      }
    }
    header_.bodyOffset = lines_.offset();
    header_.bodyFirstLine = lines_.lineNumber() + 1;
    assignRoles();
    return std::move(header_);
  }

 private:
  static bool isExactly(std::string_view line, std::initializer_list<std::string_view> expected) {
    TokenReader tokens(line);
    std::string_view token;
    for (const std::string_view word : expected) {
      if (!tokens.next(token) || token != word) return false;
    }
    return !tokens.next(token);
  }

  std::string_view expectToken(TokenReader& tokens, std::size_t lineNumber, const char* what) {
    std::string_view token;
    if (!tokens.next(token)) throwAtLine(fileName_, lineNumber, std::string("missing ") + what);
    return token;
  }

  void expectNoMore(TokenReader& tokens, std::size_t lineNumber) {
    std::string_view token;
    if (tokens.next(token)) {
      throwAtLine(fileName_, lineNumber,
                  "unexpected " + inQuotes(token) + " at the end of the line");
    }
  }

  ScalarType expectType(TokenReader& tokens, std::size_t lineNumber, const char* what) {
    const std::string_view name = expectToken(tokens, lineNumber, what);
    const std::optional<ScalarType> type = scalarTypeNamed(name);
    if (!type) {
      throwAtLine(fileName_, lineNumber,
                  "unknown property type " + inQuotes(name) +
                      " (PLY types: char uchar short ushort int uint float double, or int8 uint8 "
                      "int16 uint16 int32 uint32 float32 float64)");
    }
    return *type;
  }

  void parseFormat(TokenReader& tokens, std::size_t lineNumber) {
    const std::string_view name = expectToken(tokens, lineNumber, "format name");
    const std::optional<PlyEncoding> encoding = encodingNamed(name);
    if (!encoding) {
      throwAtLine(fileName_, lineNumber,
                  "unknown PLY format " + inQuotes(name) +
                      " (supported: ascii, binary_little_endian, binary_big_endian)");
    }
    const std::string_view version = expectToken(tokens, lineNumber, "format version");
    if (version != "1.0") {
      throwAtLine(fileName_, lineNumber,
                  "unsupported PLY version " + inQuotes(version) + " (only 1.0 is defined)");
    }
    expectNoMore(tokens, lineNumber);
    header_.encoding = *encoding;
  }

  void parseElement(TokenReader& tokens, std::size_t lineNumber) {
    PlyElement element;
    element.name = std::string(expectToken(tokens, lineNumber, "element name"));
    const std::string_view countText = expectToken(tokens, lineNumber, "element count");
    std::int64_t count = 0;
    if (detail::parseInteger(countText, count) != NumberStatus::Ok || count < 0) {
      throwAtLine(fileName_, lineNumber,
                  "element count " + inQuotes(countText) + " is not a non-negative integer");
    }
    expectNoMore(tokens, lineNumber);
    for (const PlyElement& previous : header_.elements) {
      if (previous.name == element.name) {
        throwAtLine(fileName_, lineNumber, "a second element named " + inQuotes(element.name));
      }
    }
    element.count = static_cast<std::uint64_t>(count);
    element.headerLine = lineNumber;
    header_.elements.push_back(std::move(element));
  }

  void parseProperty(TokenReader& tokens, std::size_t lineNumber) {
    PlyProperty property;
    const std::string_view first = expectToken(tokens, lineNumber, "property type");
    if (first == "list") {
      property.isList = true;
      property.countType = expectType(tokens, lineNumber, "list count type");
      if (!infoOf(property.countType).integer) {
        throwAtLine(fileName_, lineNumber, "a list count type must be an integer type");
      }
      property.valueType = expectType(tokens, lineNumber, "list value type");
    } else {
      const std::optional<ScalarType> type = scalarTypeNamed(first);
      if (!type) {
        throwAtLine(fileName_, lineNumber,
                    "unknown property type " + inQuotes(first) +
                        " (PLY types: char uchar short ushort int uint float double, or int8 "
                        "uint8 int16 uint16 int32 uint32 float32 float64, or list)");
      }
      property.valueType = *type;
    }
    property.name = std::string(expectToken(tokens, lineNumber, "property name"));
    expectNoMore(tokens, lineNumber);
    header_.elements.back().properties.push_back(std::move(property));
  }

  /// Finds the vertex and face properties the mesh needs and checks their shapes.
  void assignRoles() {
    bool hasVertexElement = false;
    for (PlyElement& element : header_.elements) {
      if (element.name == "vertex") {
        hasVertexElement = true;
        assignVertexRoles(element);
      } else if (element.name == "face") {
        assignFaceRoles(element);
      } else if (element.name == "tristrips" && element.count > 0) {
        throwAtLine(fileName_, element.headerLine,
                    "element 'tristrips' (triangle strips) is not supported");
      }
    }
    if (!hasVertexElement) throwInFile(fileName_, "the header declares no 'vertex' element");
  }

  void assignVertexRoles(PlyElement& element) {
    if (element.count > kMaxVertexCount) {
      throwAtLine(fileName_, element.headerLine, "too many vertices for 32-bit indices");
    }
    static constexpr std::array<std::pair<std::string_view, Role>, 6> kRoles = {{
        {"x", Role::X},
        {"y", Role::Y},
        {"z", Role::Z},
        {"nx", Role::NormalX},
        {"ny", Role::NormalY},
        {"nz", Role::NormalZ},
    }};
    std::array<bool, 6> found{};
    for (PlyProperty& property : element.properties) {
      for (std::size_t r = 0; r < kRoles.size(); ++r) {
        if (property.name != kRoles[r].first) continue;
        if (property.isList) {
          throwAtLine(fileName_, element.headerLine,
                      "vertex property " + inQuotes(property.name) + " must not be a list");
        }
        if (found[r]) {
          throwAtLine(fileName_, element.headerLine,
                      "vertex property " + inQuotes(property.name) + " is declared twice");
        }
        found[r] = true;
        property.role = kRoles[r].second;
      }
    }
    for (std::size_t r = 0; r < 3; ++r) {
      if (!found[r]) {
        throwAtLine(fileName_, element.headerLine,
                    "the vertex element has no property " + inQuotes(kRoles[r].first));
      }
    }
    header_.hasNormals = found[3] && found[4] && found[5];
    if (!header_.hasNormals) {
      for (PlyProperty& property : element.properties) {
        const bool isNormal = property.role == Role::NormalX || property.role == Role::NormalY ||
                              property.role == Role::NormalZ;
        if (isNormal) property.role = Role::Skip;
      }
    }
  }

  void assignFaceRoles(PlyElement& element) {
    bool found = false;
    for (PlyProperty& property : element.properties) {
      if (property.name != "vertex_indices" && property.name != "vertex_index") continue;
      if (found) {
        throwAtLine(fileName_, element.headerLine, "the face element has two vertex index lists");
      }
      if (!property.isList || !infoOf(property.valueType).integer) {
        throwAtLine(
            fileName_, element.headerLine,
            "face property " + inQuotes(property.name) + " must be a list of an integer type");
      }
      property.role = Role::VertexIndices;
      found = true;
    }
    if (!found) {
      throwAtLine(fileName_, element.headerLine,
                  "the face element has no 'vertex_indices' list property");
    }
  }

  std::string_view contents_;
  const std::string& fileName_;
  LineScanner lines_;
  PlyHeader header_;
};

// ---------------------------------------------------------------------------------------------
// Bodies: the same reading interface for text and binary data.

std::string recordName(const PlyElement& element, std::uint64_t index) {
  return "'" + element.name + "' record " + std::to_string(index);
}

/// An ASCII body: one element record per line, values separated by whitespace.
class AsciiBody {
 public:
  AsciiBody(std::string_view contents, const PlyHeader& header, const std::string& fileName)
      : lines_(contents.substr(header.bodyOffset), header.bodyFirstLine, header.bodyOffset),
        fileName_(fileName) {}

  void beginRecord(const PlyElement& element, std::uint64_t index) {
    element_ = &element;
    index_ = index;
    std::string_view line;
    do {
      if (!lines_.next(line)) {
        throwAtLine(fileName_, lines_.lineNumber(),
                    "the file ends after " + std::to_string(index) + " of " +
                        std::to_string(element.count) + " '" + element.name +
                        "' records (truncated file, or the header count is too large)");
      }
    } while (isBlank(line));
    tokens_ = TokenReader(line);
  }

  void endRecord() {
    std::string_view extra;
    if (tokens_.next(extra)) {
      fail("unexpected extra value " + inQuotes(extra) + " in " + recordName(*element_, index_));
    }
  }

  /// After the last element: only blank lines may follow.
  void finish() {
    std::string_view line;
    while (lines_.next(line)) {
      if (!isBlank(line)) {
        fail("unexpected data after the last element (the header counts are too small?)");
      }
    }
  }

  float readCoordinate(ScalarType type, const char* what) {
    const std::string_view token = nextToken(what);
    if (type == ScalarType::Float32) {
      return detail::parseFiniteFloat(token, fileName_, lines_.lineNumber(), what);
    }
    double value = 0.0;
    if (infoOf(type).integer) {
      value = static_cast<double>(integerValue(token, type, what));
    } else if (detail::parseDouble(token, value) != NumberStatus::Ok) {
      fail(std::string(what) + " " + inQuotes(token) + " is not a number");
    }
    if (!std::isfinite(value)) fail(std::string(what) + " " + inQuotes(token) + " is not finite");
    if (std::abs(value) > std::numeric_limits<float>::max()) {
      fail(std::string(what) + " " + inQuotes(token) + " is out of range for a 32-bit float");
    }
    return static_cast<float>(value);
  }

  std::int64_t readInteger(ScalarType type, const char* what) {
    return integerValue(nextToken(what), type, what);
  }

  void skip(ScalarType type, const char* what) {
    const std::string_view token = nextToken(what);
    if (infoOf(type).integer) {
      integerValue(token, type, what);
      return;
    }
    double ignored = 0.0;
    if (detail::parseDouble(token, ignored) == NumberStatus::NotANumber) {
      fail(std::string(what) + " " + inQuotes(token) + " is not a number");
    }
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throwAtLine(fileName_, lines_.lineNumber(), problem);
  }

 private:
  static bool isBlank(std::string_view line) {
    for (const char c : line) {
      if (!detail::isSpace(c)) return false;
    }
    return true;
  }

  std::string_view nextToken(const char* what) {
    std::string_view token;
    if (!tokens_.next(token)) {
      fail(recordName(*element_, index_) + " has too few values (" + what + " is missing)");
    }
    return token;
  }

  std::int64_t integerValue(std::string_view token, ScalarType type, const char* what) const {
    std::int64_t value = 0;
    const NumberStatus status = detail::parseInteger(token, value);
    if (status == NumberStatus::NotANumber) {
      fail(std::string(what) + " " + inQuotes(token) + " is not an integer");
    }
    const ScalarTypeInfo& info = infoOf(type);
    if (status == NumberStatus::OutOfRange || value < info.min || value > info.max) {
      fail(std::string(what) + " " + inQuotes(token) + " is out of range for " +
           std::string(info.name));
    }
    return value;
  }

  LineScanner lines_;
  const std::string& fileName_;
  TokenReader tokens_{std::string_view()};
  const PlyElement* element_ = nullptr;
  std::uint64_t index_ = 0;
};

/// A binary body: records packed back to back, scalars in the file's byte order.
class BinaryBody {
 public:
  BinaryBody(std::string_view contents, const PlyHeader& header, const std::string& fileName)
      : data_(contents),
        offset_(header.bodyOffset),
        order_(header.encoding == PlyEncoding::BinaryBigEndian ? ByteOrder::Big
                                                               : ByteOrder::Little),
        fileName_(fileName) {}

  void beginRecord(const PlyElement& element, std::uint64_t index) {
    element_ = &element;
    index_ = index;
    recordStart_ = offset_;
  }

  void endRecord() {}

  /// After the last element the data must end.
  void finish() const {
    if (offset_ != data_.size()) {
      throwAtByte(fileName_, offset_,
                  std::to_string(data_.size() - offset_) +
                      " unexpected bytes after the last element (the header counts are too "
                      "small?)");
    }
  }

  float readCoordinate(ScalarType type, const char* what) {
    double value = 0.0;
    switch (type) {
      case ScalarType::Float32: {
        const float single = loadScalar<float>(take(type, what), order_);
        if (!std::isfinite(single)) fail(std::string(what) + " is not finite");
        return single;
      }
      case ScalarType::Float64:
        value = loadScalar<double>(take(type, what), order_);
        break;
      default:
        value = static_cast<double>(readInteger(type, what));
        break;
    }
    if (!std::isfinite(value)) fail(std::string(what) + " is not finite");
    if (std::abs(value) > std::numeric_limits<float>::max()) {
      fail(std::string(what) + " " + std::to_string(value) + " is out of range for a 32-bit float");
    }
    return static_cast<float>(value);
  }

  std::int64_t readInteger(ScalarType type, const char* what) {
    const char* const bytes = take(type, what);
    switch (type) {
      case ScalarType::Int8:
        return loadScalar<std::int8_t>(bytes, order_);
      case ScalarType::UInt8:
        return loadScalar<std::uint8_t>(bytes, order_);
      case ScalarType::Int16:
        return loadScalar<std::int16_t>(bytes, order_);
      case ScalarType::UInt16:
        return loadScalar<std::uint16_t>(bytes, order_);
      case ScalarType::Int32:
        return loadScalar<std::int32_t>(bytes, order_);
      case ScalarType::UInt32:
        return loadScalar<std::uint32_t>(bytes, order_);
      case ScalarType::Float32:
      case ScalarType::Float64:
        break;
    }
    fail(std::string(what) + " has a floating-point type where an integer is needed");
  }

  void skip(ScalarType type, const char* what) { take(type, what); }

  [[noreturn]] void fail(const std::string& problem) const {
    throwAtByte(fileName_, valueStart_, problem);
  }

 private:
  const char* take(ScalarType type, const char* what) {
    const std::size_t size = infoOf(type).size;
    if (data_.size() - offset_ < size) {
      if (offset_ == recordStart_ && offset_ == data_.size()) {
        throwAtByte(fileName_, offset_,
                    "the file ends after " + std::to_string(index_) + " of " +
                        std::to_string(element_->count) + " '" + element_->name +
                        "' records (truncated file, or the header count is too large)");
      }
      throwAtByte(fileName_, offset_,
                  "the file ends in the middle of " + recordName(*element_, index_) + " (reading " +
                      what + "; truncated file?)");
    }
    valueStart_ = offset_;
    const char* const bytes = data_.data() + offset_;
    offset_ += size;
    return bytes;
  }

  std::string_view data_;
  std::size_t offset_;
  std::size_t recordStart_ = 0;
  std::size_t valueStart_ = 0;
  ByteOrder order_;
  const std::string& fileName_;
  const PlyElement* element_ = nullptr;
  std::uint64_t index_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Reading the elements

template <typename Body>
void skipProperty(Body& body, const PlyProperty& property) {
  if (!property.isList) {
    body.skip(property.valueType, "value");
    return;
  }
  const std::int64_t length = body.readInteger(property.countType, "list length");
  if (length < 0) body.fail("negative list length " + std::to_string(length));
  for (std::int64_t i = 0; i < length; ++i) body.skip(property.valueType, "list value");
}

template <typename Body>
void readVertices(Body& body, const PlyElement& element, bool withNormals, TriangleMesh& mesh) {
  for (std::uint64_t index = 0; index < element.count; ++index) {
    body.beginRecord(element, index);
    Eigen::Vector3f position = Eigen::Vector3f::Zero();
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();
    for (const PlyProperty& property : element.properties) {
      switch (property.role) {
        case Role::X:
          position.x() = body.readCoordinate(property.valueType, "x coordinate");
          break;
        case Role::Y:
          position.y() = body.readCoordinate(property.valueType, "y coordinate");
          break;
        case Role::Z:
          position.z() = body.readCoordinate(property.valueType, "z coordinate");
          break;
        case Role::NormalX:
          normal.x() = body.readCoordinate(property.valueType, "normal x component");
          break;
        case Role::NormalY:
          normal.y() = body.readCoordinate(property.valueType, "normal y component");
          break;
        case Role::NormalZ:
          normal.z() = body.readCoordinate(property.valueType, "normal z component");
          break;
        case Role::Skip:
        case Role::VertexIndices:
          skipProperty(body, property);
          break;
      }
    }
    body.endRecord();
    mesh.positions.push_back(position);
    if (withNormals) mesh.normals.push_back(normal);
  }
}

template <typename Body>
void readFaces(Body& body, const PlyElement& element, std::uint64_t vertexCount,
               TriangleMesh& mesh) {
  std::vector<TriangleMesh::Index> corners;
  for (std::uint64_t index = 0; index < element.count; ++index) {
    body.beginRecord(element, index);
    for (const PlyProperty& property : element.properties) {
      if (property.role != Role::VertexIndices) {
        skipProperty(body, property);
        continue;
      }
      const std::int64_t cornerCount = body.readInteger(property.countType, "face corner count");
      if (cornerCount < 3) {
        body.fail("face " + std::to_string(index) + " has " + std::to_string(cornerCount) +
                  " corners, at least 3 are needed");
      }
      corners.clear();
      for (std::int64_t c = 0; c < cornerCount; ++c) {
        const std::int64_t vertex = body.readInteger(property.valueType, "vertex index");
        if (vertex < 0) {
          body.fail("face " + std::to_string(index) + " has the negative vertex index " +
                    std::to_string(vertex));
        }
        if (static_cast<std::uint64_t>(vertex) >= vertexCount) {
          body.fail("face " + std::to_string(index) + " has vertex index " +
                    std::to_string(vertex) + ", but the file has only " +
                    std::to_string(vertexCount) + " vertices (indices count from 0)");
        }
        corners.push_back(static_cast<TriangleMesh::Index>(vertex));
      }
      for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
        mesh.triangles.push_back({corners[0], corners[i], corners[i + 1]});
      }
    }
    body.endRecord();
  }
}

template <typename Body>
TriangleMesh readBody(Body& body, const PlyHeader& header, std::size_t contentSize,
                      const std::string& fileName) {
  TriangleMesh mesh;
  std::uint64_t vertexCount = 0;
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex") vertexCount = element.count;
  }
  // A vertex record holds at least three values of at least one byte each, so the file size
  // bounds what is worth reserving (the header count may be wrong).
  const std::uint64_t reservable = std::min<std::uint64_t>(vertexCount, contentSize / 3);
  mesh.positions.reserve(reservable);
  if (header.hasNormals) mesh.normals.reserve(reservable);
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex") {
      readVertices(body, element, header.hasNormals, mesh);
    } else if (element.name == "face") {
      readFaces(body, element, vertexCount, mesh);
    } else if (!element.properties.empty()) {  // records without properties take no data
      for (std::uint64_t index = 0; index < element.count; ++index) {
        body.beginRecord(element, index);
        for (const PlyProperty& property : element.properties) skipProperty(body, property);
        body.endRecord();
      }
    }
  }
  body.finish();
  if (mesh.positions.empty()) throwInFile(fileName, "the file holds no vertices");
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// Writing

bool hasScalars(const VertexAttributes* attributes) {
  return attributes != nullptr && !attributes->scalars.empty();
}

bool hasColors(const VertexAttributes* attributes) {
  return attributes != nullptr && !attributes->colors.empty();
}

std::string headerText(const TriangleMesh& mesh, PlyEncoding encoding,
                       const VertexAttributes* attributes) {
  std::string header = "ply\nformat ";
  switch (encoding) {
    case PlyEncoding::Ascii:
      header += "ascii";
      break;
    case PlyEncoding::BinaryLittleEndian:
      header += "binary_little_endian";
      break;
    case PlyEncoding::BinaryBigEndian:
      header += "binary_big_endian";
      break;
  }
  header += " 1.0\ncomment written by d2vdb\nelement vertex ";
  detail::appendUnsigned(header, mesh.positions.size());
  header += "\nproperty float x\nproperty float y\nproperty float z\n";
  if (mesh.hasNormals()) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (hasScalars(attributes)) header += "property float " + attributes->scalarName + "\n";
  if (attributes != nullptr) {
    for (const auto& more : attributes->moreScalars)
      header += "property float " + more.first + "\n";
  }
  if (hasColors(attributes)) {
    header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  }
  header += "element face ";
  detail::appendUnsigned(header, mesh.triangles.size());
  header += "\nproperty list uchar uint vertex_indices\nend_header\n";
  return header;
}

void appendAsciiBody(std::string& buffer, std::ostream& out, const TriangleMesh& mesh,
                     const VertexAttributes* attributes) {
  const bool withNormals = mesh.hasNormals();
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      if (axis > 0) buffer += ' ';
      detail::appendFloat(buffer, mesh.positions[v][axis]);
    }
    if (withNormals) {
      for (int axis = 0; axis < 3; ++axis) {
        buffer += ' ';
        detail::appendFloat(buffer, mesh.normals[v][axis]);
      }
    }
    if (hasScalars(attributes)) {
      buffer += ' ';
      detail::appendFloat(buffer, attributes->scalars[v]);
    }
    if (attributes != nullptr) {
      for (const auto& more : attributes->moreScalars) {
        buffer += ' ';
        detail::appendFloat(buffer, more.second[v]);
      }
    }
    if (hasColors(attributes)) {
      for (const std::uint8_t channel : attributes->colors[v]) {
        buffer += ' ';
        detail::appendUnsigned(buffer, channel);
      }
    }
    buffer += '\n';
    detail::flushBuffer(buffer, out);
  }
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    buffer += '3';
    for (const TriangleMesh::Index index : triangle) {
      buffer += ' ';
      detail::appendUnsigned(buffer, index);
    }
    buffer += '\n';
    detail::flushBuffer(buffer, out);
  }
}

void appendBinaryBody(std::string& buffer, std::ostream& out, const TriangleMesh& mesh,
                      ByteOrder order, const VertexAttributes* attributes) {
  const bool withNormals = mesh.hasNormals();
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      detail::appendScalar(buffer, mesh.positions[v][axis], order);
    }
    if (withNormals) {
      for (int axis = 0; axis < 3; ++axis) {
        detail::appendScalar(buffer, mesh.normals[v][axis], order);
      }
    }
    if (hasScalars(attributes)) detail::appendScalar(buffer, attributes->scalars[v], order);
    if (attributes != nullptr) {
      for (const auto& more : attributes->moreScalars) {
        detail::appendScalar(buffer, more.second[v], order);
      }
    }
    if (hasColors(attributes)) {
      for (const std::uint8_t channel : attributes->colors[v]) {
        detail::appendScalar(buffer, channel, order);
      }
    }
    detail::flushBuffer(buffer, out);
  }
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    detail::appendScalar(buffer, std::uint8_t{3}, order);
    for (const TriangleMesh::Index index : triangle) {
      detail::appendScalar(buffer, std::uint32_t{index}, order);
    }
    detail::flushBuffer(buffer, out);
  }
}

}  // namespace

TriangleMesh parsePly(std::string_view contents, const std::string& nameForMessages) {
  const PlyHeader header = HeaderParser(contents, nameForMessages).parse();
  if (header.encoding == PlyEncoding::Ascii) {
    AsciiBody body(contents, header, nameForMessages);
    return readBody(body, header, contents.size(), nameForMessages);
  }
  BinaryBody body(contents, header, nameForMessages);
  return readBody(body, header, contents.size(), nameForMessages);
}

TriangleMesh readPly(std::istream& in, const std::string& nameForMessages) {
  const std::string contents = detail::readStreamContents(in, nameForMessages);
  return parsePly(contents, nameForMessages);
}

void writePly(std::ostream& out, const TriangleMesh& mesh, PlyEncoding encoding,
              const VertexAttributes* attributes) {
  detail::checkMeshIsWritable(mesh, "PLY");
  if (attributes != nullptr) detail::checkVertexAttributes(mesh, *attributes);
  std::string buffer = headerText(mesh, encoding, attributes);
  switch (encoding) {
    case PlyEncoding::Ascii:
      appendAsciiBody(buffer, out, mesh, attributes);
      break;
    case PlyEncoding::BinaryLittleEndian:
      appendBinaryBody(buffer, out, mesh, ByteOrder::Little, attributes);
      break;
    case PlyEncoding::BinaryBigEndian:
      appendBinaryBody(buffer, out, mesh, ByteOrder::Big, attributes);
      break;
  }
  detail::flushBuffer(buffer, out, true);
}

}  // namespace d2vdb::detail
