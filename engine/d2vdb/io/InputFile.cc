// loadInput(): recognising a file's format by content, the kinds a caller accepts, and reading it
// once into the right representation.
#include "d2vdb/io/InputFile.h"

#include <array>
#include <charconv>
#include <cstring>
#include <fstream>
#include <string_view>
#include <system_error>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/core/detail/FileExtension.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/FieldGrids.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/io/detail/JsonDocuments.h"
#include "d2vdb/io/detail/JsonReader.h"
#include "d2vdb/io/detail/TextFile.h"

namespace d2vdb {
namespace {

// The formats a file can be in; each yields one or more InputKinds.
enum class FileFormat { Unknown, Vdb, Ply, Stl, Obj, Xyz, Json };

// How many bytes of a file its format is recognised from.
constexpr std::size_t kHeadBytes = 4096;

// ---- the kinds: one row each (InputKind order) -----------------------------------------------

struct KindRow {
  InputKind kind;
  const char* name;         // inputKindName()
  const char* description;  // for "is ..." and "must be ..."
};

constexpr std::array<KindRow, 9> kKinds = {{
    {InputKind::Mesh, "mesh", "a triangle mesh (.obj, .ply, .stl)"},
    {InputKind::PointSet, "points", "a point set (.xyz, .ply)"},
    {InputKind::LevelSet, "level set", "a level set (.vdb)"},
    {InputKind::Field, "field", "an approximant field or a level set (.vdb)"},
    {InputKind::VdbGrids, "grids", "a .vdb grid file"},
    {InputKind::Curve, "curve", "a B-spline curve (.json)"},
    {InputKind::Surface, "surface", "a B-spline surface (.json)"},
    {InputKind::Polylines, "polyline", "a polyline (.json)"},
    {InputKind::SupportFunction, "support function", "a support function (.json)"},
}};
constexpr bool rowsFollowInputKind() {
  for (std::size_t i = 0; i < kKinds.size(); ++i) {
    if (static_cast<std::size_t>(kKinds[i].kind) != i) return false;
  }
  return true;
}
static_assert(std::variant_size_v<LoadedInput::Value> == kKinds.size() && rowsFollowInputKind(),
              "every alternative of LoadedInput has its row in kKinds, in InputKind order");

// JSON documents by their "type" (a slice file has none; see jsonKind()).
struct JsonTypeRow {
  const char* type;
  InputKind kind;
};
constexpr std::array<JsonTypeRow, 4> kJsonTypes = {{
    {"bspline_curve", InputKind::Curve},
    {"bspline_surface", InputKind::Surface},
    {"polyline", InputKind::Polylines},
    {kSupportFunctionJsonType, InputKind::SupportFunction},
}};

// "a, b or c" of the accepted kinds' descriptions.
std::string acceptedList(InputKinds accepted) {
  std::vector<std::string> names;
  for (const KindRow& row : kKinds) {
    if (accepted.contains(row.kind)) names.emplace_back(row.description);
  }
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i) {
    list += (i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ")) + names[i];
  }
  return list;
}

[[noreturn]] void rejectKind(const std::filesystem::path& path, const std::string& whatItIs,
                             InputKinds accepted, const LoadOptions& options) {
  throw InputError(quotedPath(path) + " is " + whatItIs + "; " + options.purpose + " must be " +
                   acceptedList(accepted));
}

// ---- recognising the format --------------------------------------------------------------------

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

bool startsWith(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

// OBJ or .xyz from the first line that is neither blank nor a '#' comment; Unknown otherwise.
FileFormat textFormat(std::string_view head) {
  static constexpr std::array<std::string_view, 12> kObjKeywords = {
      "v", "vn", "vt", "vp", "f", "l", "p", "o", "g", "s", "mtllib", "usemtl"};
  while (!head.empty()) {
    const std::size_t end = head.find('\n');
    if (end == std::string_view::npos) return FileFormat::Unknown;  // the line may go on
    std::string_view line = head.substr(0, end);
    head.remove_prefix(end + 1);
    while (!line.empty() && isBlank(line.front())) line.remove_prefix(1);
    if (line.empty() || line.front() == '#') continue;
    std::size_t length = 0;
    while (length < line.size() && !isBlank(line[length])) ++length;
    const std::string_view token = line.substr(0, length);
    for (const std::string_view keyword : kObjKeywords) {
      if (token == keyword) return FileFormat::Obj;
    }
    std::string_view digits = token;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    double number = 0.0;
    const auto [stop, error] =
        std::from_chars(digits.data(), digits.data() + digits.size(), number);
    const bool isNumber = !digits.empty() && stop == digits.data() + digits.size() &&
                          (error == std::errc() || error == std::errc::result_out_of_range);
    return isNumber ? FileFormat::Xyz : FileFormat::Unknown;
  }
  return FileFormat::Unknown;
}

FileFormat formatFromContent(std::string_view head, std::uint64_t size) {
  std::int64_t magic = 0;
  if (head.size() >= sizeof(magic)) {
    std::memcpy(&magic, head.data(), sizeof(magic));
    if (magic == openvdb::OPENVDB_MAGIC) return FileFormat::Vdb;
  }
  if (startsWith(head, "ply\n") || startsWith(head, "ply\r\n")) return FileFormat::Ply;
  std::string_view text = head;
  if (startsWith(text, "\xEF\xBB\xBF")) text.remove_prefix(3);  // a UTF-8 byte order mark
  while (!text.empty() && isBlank(text.front())) text.remove_prefix(1);
  if (startsWith(text, "{")) return FileFormat::Json;
  if (startsWith(head, "solid")) return FileFormat::Stl;
  if (size >= 84 && head.size() >= 84) {
    // A binary STL: an 80-byte header, the triangle count (uint32, little endian), 50 bytes each.
    const auto* bytes = reinterpret_cast<const unsigned char*>(head.data() + 80);
    const std::uint32_t triangles = std::uint32_t{bytes[0]} | std::uint32_t{bytes[1]} << 8 |
                                    std::uint32_t{bytes[2]} << 16 | std::uint32_t{bytes[3]} << 24;
    if (84 + 50 * std::uint64_t{triangles} == size) return FileFormat::Stl;
  }
  return textFormat(head);
}

FileFormat formatFromExtension(const std::filesystem::path& path) {
  const std::string extension = detail::lowerExtension(path);
  if (extension == ".vdb") return FileFormat::Vdb;
  if (extension == ".ply") return FileFormat::Ply;
  if (extension == ".json") return FileFormat::Json;
  if (extension == ".stl") return FileFormat::Stl;
  if (extension == ".obj") return FileFormat::Obj;
  if (extension == ".xyz") return FileFormat::Xyz;
  return FileFormat::Unknown;
}

// Checks that `path` is a readable, non-empty regular file and returns its first bytes and size.
std::pair<std::string, std::uint64_t> readHead(const std::filesystem::path& path,
                                               InputKinds accepted, const LoadOptions& options) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) {
    throw InputError("the file " + quotedPath(path) + " does not exist");
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw InputError(
        quotedPath(path) + " is " +
        (std::filesystem::is_directory(status) ? "a directory" : "not a regular file") + "; " +
        options.purpose + " must be " + acceptedList(accepted));
  }
  const std::uint64_t size = std::filesystem::file_size(path, error);
  if (error)
    throw InputError("cannot determine the size of " + quotedPath(path) + ": " + error.message());
  if (size == 0) {
    throw InputError("the file " + quotedPath(path) + " is empty; " + options.purpose +
                     " must be " + acceptedList(accepted));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open " + quotedPath(path) + " for reading (permissions?)");
  std::string head(static_cast<std::size_t>(std::min<std::uint64_t>(size, kHeadBytes)), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw InputError("cannot read " + quotedPath(path) + ": read error");
  return {std::move(head), size};
}

// ---- reading each format -----------------------------------------------------------------------

LoadedInput loadVdb(const std::filesystem::path& path, InputKinds accepted,
                    const LoadOptions& options) {
  if (!accepted.contains(InputKind::Field) && !accepted.contains(InputKind::LevelSet) &&
      !accepted.contains(InputKind::VdbGrids)) {
    rejectKind(path, "a .vdb grid file", accepted, options);
  }
  std::vector<openvdb::GridBase::Ptr> grids = readAllGrids(path);
  const bool storesField = isFieldFile(grids);
  if (accepted.contains(InputKind::Field) &&
      (storesField || !accepted.contains(InputKind::LevelSet))) {
    if (storesField) {
      return {
          path,
          FieldInput{fieldFromGrids(grids, path.string(), options.field, options.progress), true}};
    }
    const openvdb::FloatGrid::Ptr levelSet = openvdb::gridPtrCast<openvdb::FloatGrid>(
        selectGrid(grids, quotedPath(path), options.gridName, ScalarGridTypes::Float));
    return {path,
            FieldInput{ApproximantField::fromLevelSet(levelSet, options.field, options.progress),
                       false}};
  }
  if (accepted.contains(InputKind::LevelSet)) {
    openvdb::GridBase::Ptr grid =
        selectGrid(grids, quotedPath(path), options.gridName, options.gridTypes);
    return {path, LevelSetInput{std::move(grids), std::move(grid)}};
  }
  if (accepted.contains(InputKind::VdbGrids)) return {path, VdbGridsInput{std::move(grids)}};
  rejectKind(path, "an approximant field (.vdb)", accepted, options);
}

LoadedInput loadPly(const std::filesystem::path& path, InputKinds accepted,
                    const LoadOptions& options) {
  if (!accepted.contains(InputKind::Mesh) && !accepted.contains(InputKind::PointSet)) {
    rejectKind(path, "a PLY file (a mesh or a point set)", accepted, options);
  }
  TriangleMesh mesh = readMesh(path, MeshFormat::Ply);
  if (accepted.contains(InputKind::Mesh) &&
      (!mesh.triangles.empty() || !accepted.contains(InputKind::PointSet))) {
    return {path, MeshInput{std::move(mesh), MeshFormat::Ply}};
  }
  PointSetInput points;
  points.points.reserve(mesh.positions.size());
  for (const Eigen::Vector3f& position : mesh.positions) {
    points.points.push_back(position.cast<double>());
  }
  return {path, std::move(points)};
}

LoadedInput loadMesh(const std::filesystem::path& path, MeshFormat format, InputKinds accepted,
                     const LoadOptions& options) {
  if (!accepted.contains(InputKind::Mesh)) {
    rejectKind(path, "a triangle mesh (" + meshFormatName(format) + ")", accepted, options);
  }
  return {path, MeshInput{readMesh(path, format), format}};
}

LoadedInput loadXyz(const std::filesystem::path& path, InputKinds accepted,
                    const LoadOptions& options) {
  if (!accepted.contains(InputKind::PointSet)) {
    rejectKind(path, "a point set (.xyz)", accepted, options);
  }
  return {path, PointSetInput{parseXyz(detail::readTextFile(path, "point file"), path.string())}};
}

// The kind of a parsed JSON document, or an InputError saying what it is instead.
InputKind jsonKind(const detail::Json& document, const std::filesystem::path& path) {
  if (document.is_object()) {
    const auto type = document.find("type");
    if (type == document.end()) {
      if (document.contains("polylines")) return InputKind::Polylines;  // a slice file
    } else if (type->is_string()) {
      for (const JsonTypeRow& row : kJsonTypes) {
        if (*type == row.type) return row.kind;
      }
    }
  }
  std::string known;
  for (const JsonTypeRow& row : kJsonTypes) {
    known += (known.empty() ? "\"" : "\", \"") + std::string(row.type);
  }
  const auto type = document.is_object() ? document.find("type") : document.end();
  throw InputError("JSON file " + quotedPath(path) + " is not one d2vdb reads: " +
                   (type == document.end() ? std::string("it has no \"type\"")
                                           : "its \"type\" is " + type->dump()) +
                   " (d2vdb reads the types " + known +
                   "\", and the polylines of 'd2vdb slice --polylines')");
}

LoadedInput loadJson(const std::filesystem::path& path, InputKinds accepted,
                     const LoadOptions& options) {
  const std::string text = detail::readTextFile(path, "JSON file");
  const detail::Json document = detail::JsonFieldReader("JSON file", path.string()).parse(text);
  const InputKind kind = jsonKind(document, path);
  if (!accepted.contains(kind)) {
    std::string description = kKinds[static_cast<std::size_t>(kind)].description;
    rejectKind(path, description, accepted, options);
  }
  switch (kind) {
    case InputKind::Curve:
      return {path, detail::curveFromJson(document, path.string())};
    case InputKind::Surface:
      return {path, detail::surfaceFromJson(document, path.string())};
    case InputKind::Polylines:
      return {path, PolylinesInput{detail::polylinesFromJson(document, path.string())}};
    case InputKind::SupportFunction:
      return {path, detail::supportFunctionFromJson(document, path.string())};
    default:
      break;
  }
  throw RuntimeFailure("loadInput: JSON kind without a reader");
}

}  // namespace

LoadedInput loadInput(const std::filesystem::path& path, InputKinds accepted,
                      const LoadOptions& options) {
  if (accepted.empty()) throw RuntimeFailure("loadInput: no kind of input is accepted");
  const auto [head, size] = readHead(path, accepted, options);
  FileFormat format = formatFromContent(head, size);
  if (format == FileFormat::Unknown) format = formatFromExtension(path);
  switch (format) {
    case FileFormat::Vdb:
      return loadVdb(path, accepted, options);
    case FileFormat::Ply:
      return loadPly(path, accepted, options);
    case FileFormat::Stl:
      return loadMesh(path, MeshFormat::Stl, accepted, options);
    case FileFormat::Obj:
      return loadMesh(path, MeshFormat::Obj, accepted, options);
    case FileFormat::Xyz:
      return loadXyz(path, accepted, options);
    case FileFormat::Json:
      return loadJson(path, accepted, options);
    case FileFormat::Unknown:
      break;
  }
  const std::string extension = path.extension().string();
  throw InputError("cannot tell what " + quotedPath(path) +
                   " is: its content is none of the formats d2vdb reads (.vdb, OBJ, PLY, STL, "
                   ".xyz, JSON), and " +
                   (extension.empty() ? std::string("it has no extension")
                                      : "neither is its extension '" + extension + "'") +
                   "; " + options.purpose + " must be " + acceptedList(accepted));
}

std::string describeInputKind(InputKind kind) {
  return kKinds[static_cast<std::size_t>(kind)].description;
}

void detail::throwWrongInputKind(const std::filesystem::path& path, InputKind loaded,
                                 InputKind wanted) {
  throw RuntimeFailure("loadInput: " + quotedPath(path) + " was loaded as " +
                       describeInputKind(loaded) + ", not as " + describeInputKind(wanted));
}

const char* inputKindName(InputKind kind) {
  return kKinds[static_cast<std::size_t>(kind)].name;
}

}  // namespace d2vdb
