#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/io/detail/JsonReader.h"

namespace d2vdb::detail {

std::string describeJsonType(const Json& value) {
  switch (value.type()) {
    case Json::value_t::null:
      return "null";
    case Json::value_t::boolean:
      return "a boolean";
    case Json::value_t::string:
      return "a string";
    case Json::value_t::array:
      return "an array";
    case Json::value_t::object:
      return "an object";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float:
      return "a number";
    default:
      return "an unsupported value";
  }
}

std::string jsonNumberText(double value) {
  return Json(value).dump();
}

std::string memberPath(const std::string& objectPath, const std::string& key) {
  return objectPath.empty() ? key : objectPath + "." + key;
}

std::string elementPath(const std::string& arrayPath, std::size_t index) {
  return arrayPath + "[" + std::to_string(index) + "]";
}

JsonFieldReader::JsonFieldReader(std::string fileKind, std::string sourceName)
    : fileKind_(std::move(fileKind)), source_(std::move(sourceName)) {}

void JsonFieldReader::fail(const std::string& path, const std::string& problem) const {
  if (path.empty()) throw InputError(fileKind_ + " '" + source_ + "': " + problem);
  throw InputError(fileKind_ + " '" + source_ + "', field '" + path + "': " + problem);
}

Json JsonFieldReader::parse(const std::string& text) const {
  // nlohmann keeps the last of duplicate keys; the formats forbid them (which value was meant?).
  // The callback tracks the path of every object and array to name the duplicate.
  struct Frame {
    bool isObject;
    std::string key;        // objects: the current member
    std::size_t index = 0;  // arrays: the current element
    std::set<std::string> keys;
  };
  std::vector<Frame> frames;
  const auto pathOf = [&frames](std::size_t depth) {
    std::string path;
    for (std::size_t i = 0; i < depth; ++i) {
      path =
          frames[i].isObject ? memberPath(path, frames[i].key) : elementPath(path, frames[i].index);
    }
    return path;
  };
  const auto elementDone = [&frames] {
    if (!frames.empty() && !frames.back().isObject) ++frames.back().index;
  };
  const Json::parser_callback_t callback = [&](int, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
        frames.push_back({true, "", 0, {}});
        break;
      case Json::parse_event_t::array_start:
        frames.push_back({false, "", 0, {}});
        break;
      case Json::parse_event_t::key: {
        Frame& frame = frames.back();
        frame.key = parsed.get<std::string>();
        if (!frame.keys.insert(frame.key).second) {
          fail(pathOf(frames.size()), "appears twice in the same object (duplicate key)");
        }
        break;
      }
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        frames.pop_back();
        elementDone();
        break;
      case Json::parse_event_t::value:
        elementDone();
        break;
    }
    return true;
  };
  try {
    return Json::parse(text, callback);
  } catch (const Json::parse_error& error) {
    fail("", "invalid JSON at byte " + std::to_string(error.byte) + ": " + error.what());
  } catch (const Json::exception& error) {
    // e.g. out_of_range 406 for a number such as 1e999 that overflows a double.
    fail("", std::string("invalid JSON: ") + error.what());
  }
}

const Json& JsonFieldReader::object(const Json& value, const std::string& path) const {
  if (!value.is_object()) fail(path, "expected a JSON object, got " + describeJsonType(value));
  return value;
}

void JsonFieldReader::checkTypeAndVersion(const Json& root, const std::string& expectedType,
                                          int version) const {
  const std::string type = string(root, "type");
  if (type != expectedType) {
    fail("type", "is \"" + type + "\", expected \"" + expectedType + "\"");
  }
  const int found = integer(root, "version");
  if (found != version) {
    fail("version", "version " + std::to_string(found) +
                        " is not supported (this reader reads version " + std::to_string(version) +
                        ")");
  }
}

void JsonFieldReader::rejectUnknownFields(const Json& object,
                                          std::initializer_list<const char*> allowed,
                                          const std::string& objectKind,
                                          const std::string& objectPath) const {
  for (const auto& item : object.items()) {
    bool known = false;
    for (const char* name : allowed) known = known || item.key() == name;
    if (!known) {
      std::string list;
      for (const char* name : allowed) list += (list.empty() ? "" : ", ") + std::string(name);
      fail(memberPath(objectPath, item.key()),
           "is not a field of a " + objectKind + " (expected " + list + ")");
    }
  }
}

const Json& JsonFieldReader::field(const Json& object, const char* key, const char* expected,
                                   const std::string& objectPath) const {
  const auto found = object.find(key);
  if (found == object.end()) {
    fail(memberPath(objectPath, key), std::string("is missing (expected ") + expected + ")");
  }
  return *found;
}

std::string JsonFieldReader::string(const Json& object, const char* key,
                                    const std::string& objectPath) const {
  const Json& value = field(object, key, "a string", objectPath);
  if (!value.is_string()) {
    fail(memberPath(objectPath, key), "expected a string, got " + describeJsonType(value));
  }
  return value.get<std::string>();
}

int JsonFieldReader::integer(const Json& object, const char* key,
                             const std::string& objectPath) const {
  const Json& value = field(object, key, "an integer", objectPath);
  const std::string path = memberPath(objectPath, key);
  if (!value.is_number_integer()) {
    fail(path, "expected an integer, got " + describeJsonType(value));
  }
  const auto number = value.get<long long>();
  if (number < -1000000 || number > 1000000)
    fail(path, "value " + value.dump() + " is out of range");
  return static_cast<int>(number);
}

bool JsonFieldReader::boolean(const Json& object, const char* key,
                              const std::string& objectPath) const {
  const Json& value = field(object, key, "true or false", objectPath);
  if (!value.is_boolean()) {
    fail(memberPath(objectPath, key), "expected true or false, got " + describeJsonType(value));
  }
  return value.get<bool>();
}

bool JsonFieldReader::optionalBoolean(const Json& object, const char* key,
                                      const std::string& objectPath) const {
  return object.contains(key) && boolean(object, key, objectPath);
}

double JsonFieldReader::number(const Json& value, const std::string& path) const {
  if (!value.is_number()) fail(path, "expected a number, got " + describeJsonType(value));
  const double number = value.get<double>();
  if (!std::isfinite(number)) fail(path, "value " + value.dump() + " is not a finite number");
  return number;
}

const Json& JsonFieldReader::array(const Json& value, const std::string& path) const {
  if (!value.is_array()) fail(path, "expected an array, got " + describeJsonType(value));
  return value;
}

Eigen::Vector3d JsonFieldReader::point(const Json& value, const std::string& path,
                                       int dimension) const {
  const Json& coordinates = array(value, path);
  if (coordinates.size() != static_cast<std::size_t>(dimension)) {
    fail(path, "has " + std::to_string(coordinates.size()) + " coordinates, expected " +
                   std::to_string(dimension));
  }
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  for (int axis = 0; axis < dimension; ++axis) {
    point[axis] = number(coordinates[static_cast<std::size_t>(axis)],
                         elementPath(path, static_cast<std::size_t>(axis)));
  }
  return point;
}

}  // namespace d2vdb::detail
