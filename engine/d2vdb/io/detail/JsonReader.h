// Internal to the io module: strict reading of d2vdb's JSON file formats (spline, polyline and
// slice files). Every failure is an InputError naming the file and the JSON path of the field.
#pragma once

#include <nlohmann/json.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <initializer_list>
#include <string>

namespace d2vdb::detail {

using Json = nlohmann::json;

/// How a JSON value is named in messages: "null", "a boolean", "a string", "a number", ...
std::string describeJsonType(const Json& value);

/// The shortest text that reads back as exactly `value` (nlohmann's number formatting).
std::string jsonNumberText(double value);

/// "objectPath.key", or "key" at the root (objectPath empty).
std::string memberPath(const std::string& objectPath, const std::string& key);

/// "arrayPath[index]".
std::string elementPath(const std::string& arrayPath, std::size_t index);

/// Checks values of one parsed document and throws InputError
/// "<fileKind> '<source>', field '<path>': <problem>" (or without the field part at the root).
/// Accessors taking `objectPath` read the member `key` of the object found at that path ("" for
/// the root object).
class JsonFieldReader {
 public:
  /// `fileKind` e.g. "spline file"; `sourceName` the file name (or "<string>").
  JsonFieldReader(std::string fileKind, std::string sourceName);

  /// Throws InputError for the field at `path` ("" = the document as a whole).
  [[noreturn]] void fail(const std::string& path, const std::string& problem) const;

  /// Parses `text`; invalid JSON fails with nlohmann's byte offset, a key that appears twice in
  /// one object fails naming its path.
  Json parse(const std::string& text) const;

  /// `value` itself when it is an object, else fails at `path`.
  const Json& object(const Json& value, const std::string& path) const;

  /// Checks the root object's "type" (must be `expectedType`) and "version" (must be
  /// `version`), failing at that field otherwise.
  void checkTypeAndVersion(const Json& root, const std::string& expectedType, int version) const;

  /// Fails for the first member of `object` whose name is not in `allowed`, saying it is not a
  /// field of `objectKind` and listing the allowed names.
  void rejectUnknownFields(const Json& object, std::initializer_list<const char*> allowed,
                           const std::string& objectKind, const std::string& objectPath = "") const;

  /// The member `key`; fails "is missing (expected <expected>)" when absent.
  const Json& field(const Json& object, const char* key, const char* expected,
                    const std::string& objectPath = "") const;

  /// A required string member.
  std::string string(const Json& object, const char* key, const std::string& objectPath = "") const;

  /// A required integer member in [-10^6, 10^6].
  int integer(const Json& object, const char* key, const std::string& objectPath = "") const;

  /// A required true/false member.
  bool boolean(const Json& object, const char* key, const std::string& objectPath = "") const;

  /// An optional true/false member (false when absent).
  bool optionalBoolean(const Json& object, const char* key,
                       const std::string& objectPath = "") const;

  /// A finite number at `path`.
  double number(const Json& value, const std::string& path) const;

  /// `value` itself when it is an array, else fails at `path`.
  const Json& array(const Json& value, const std::string& path) const;

  /// An array of exactly `dimension` (2 or 3) finite numbers; z = 0 when dimension is 2.
  Eigen::Vector3d point(const Json& value, const std::string& path, int dimension) const;

 private:
  std::string fileKind_;
  std::string source_;
};

}  // namespace d2vdb::detail
