#include "d2vdb/mesh/detail/MeshFileCommon.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <istream>
#include <ostream>
#include <system_error>

#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/detail/MeshIndexCheck.h"

namespace d2vdb::detail {
namespace {

constexpr std::size_t kFlushThreshold = std::size_t{1} << 20;

bool isFinite(const Eigen::Vector3f& vector) {
  return vector.allFinite();
}

}  // namespace

void throwInFile(const std::string& fileName, const std::string& problem) {
  throw InputError(fileName + ": " + problem);
}

void throwAtLine(const std::string& fileName, std::size_t lineNumber, const std::string& problem) {
  throw InputError(fileName + ", line " + std::to_string(lineNumber) + ": " + problem);
}

void throwAtByte(const std::string& fileName, std::size_t byteOffset, const std::string& problem) {
  throw InputError(fileName + ", byte " + std::to_string(byteOffset) + ": " + problem);
}

std::string inQuotes(std::string_view text) {
  constexpr std::size_t kMaxShown = 40;
  std::string result = "'";
  for (const char c : text.substr(0, kMaxShown)) {
    const auto byte = static_cast<unsigned char>(c);
    result += (byte >= 0x20 && byte < 0x7F) ? c : '?';
  }
  if (text.size() > kMaxShown) result += "...";
  result += "'";
  return result;
}

std::string readFileContents(const std::filesystem::path& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) {
    throw InputError("cannot read '" + path.string() + "': no such file");
  }
  if (std::filesystem::is_directory(status)) {
    throw InputError("cannot read '" + path.string() + "': it is a directory, not a file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError("cannot open '" + path.string() + "' for reading (permission denied?)");
  }
  // Read straight into a buffer of the file's size (a growing buffer would copy big files
  // several times); anything beyond that size (a file still being written) is appended.
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  std::string contents;
  if (!error && size > 0) {
    contents.resize(static_cast<std::size_t>(size));
    in.read(contents.data(), static_cast<std::streamsize>(size));
    contents.resize(static_cast<std::size_t>(in.gcount()));
    if (in.bad()) {
      throw InputError("cannot read '" + path.string() + "': read error after " +
                       std::to_string(contents.size()) + " bytes");
    }
    if (!in) return contents;  // the file ended early (it shrank): what was read is the file
  }
  contents += readStreamContents(in, path.string());
  return contents;
}

std::string readStreamContents(std::istream& in, const std::string& nameForMessages) {
  std::string contents;
  // Reserve the rest of a seekable stream; other streams grow as they are read.
  const std::istream::pos_type start = in.tellg();
  if (start != std::istream::pos_type(-1) && in.seekg(0, std::ios::end)) {
    const std::istream::pos_type end = in.tellg();
    in.seekg(start);
    if (end != std::istream::pos_type(-1) && end > start) {
      contents.reserve(static_cast<std::size_t>(end - start));
    }
  }
  in.clear(in.rdstate() & ~std::ios::failbit);
  std::array<char, 1 << 16> chunk{};
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    contents.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad())
    throwInFile(nameForMessages, "read error after " + std::to_string(contents.size()) + " bytes");
  return contents;
}

void checkMeshIsWritable(const TriangleMesh& mesh, const char* formatName) {
  const std::string context = std::string("cannot write the mesh as ") + formatName + ": ";
  if (mesh.positions.empty()) throw InputError(context + "it has no vertices");
  detail::checkTriangleIndices(mesh, context.substr(0, context.size() - 2).c_str());
  const std::size_t vertexCount = mesh.positions.size();
  for (std::size_t v = 0; v < vertexCount; ++v) {
    if (!isFinite(mesh.positions[v])) {
      throw InputError(context + "vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
  }
  if (mesh.hasNormals()) {
    for (std::size_t v = 0; v < vertexCount; ++v) {
      if (!isFinite(mesh.normals[v])) {
        throw InputError(context + "the normal of vertex " + std::to_string(v) +
                         " has a non-finite component");
      }
    }
  }
}

void checkVertexAttributes(const TriangleMesh& mesh, const VertexAttributes& attributes) {
  const std::size_t count = mesh.positions.size();
  if (!attributes.scalars.empty()) {
    if (attributes.scalars.size() != count) {
      throw InputError("cannot write the mesh: " + std::to_string(attributes.scalars.size()) +
                       " vertex scalars for " + std::to_string(count) + " vertices");
    }
    const std::string& name = attributes.scalarName;
    const bool identifier = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
    });
    if (!identifier) {
      throw InputError("cannot write the mesh: the vertex scalar name '" + name +
                       "' is not a plain identifier");
    }
    for (std::size_t v = 0; v < count; ++v) {
      if (!std::isfinite(attributes.scalars[v])) {
        throw InputError("cannot write the mesh: the " + name + " of vertex " + std::to_string(v) +
                         " is not finite");
      }
    }
  }
  std::vector<std::string> names = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"};
  if (!attributes.scalars.empty()) names.push_back(attributes.scalarName);
  for (const auto& [name, values] : attributes.moreScalars) {
    const bool identifier = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
    });
    if (!identifier) {
      throw InputError("cannot write the mesh: the vertex scalar name '" + name +
                       "' is not a plain identifier");
    }
    if (std::find(names.begin(), names.end(), name) != names.end()) {
      throw InputError("cannot write the mesh: the vertex property '" + name + "' appears twice");
    }
    names.push_back(name);
    if (values.size() != count) {
      throw InputError("cannot write the mesh: " + std::to_string(values.size()) + " values of " +
                       name + " for " + std::to_string(count) + " vertices");
    }
    for (std::size_t v = 0; v < count; ++v) {
      if (!std::isfinite(values[v])) {
        throw InputError("cannot write the mesh: the " + name + " of vertex " + std::to_string(v) +
                         " is not finite");
      }
    }
  }
  if (!attributes.colors.empty() && attributes.colors.size() != count) {
    throw InputError("cannot write the mesh: " + std::to_string(attributes.colors.size()) +
                     " vertex colours for " + std::to_string(count) + " vertices");
  }
}

void appendFloat(std::string& out, float value) {
  std::array<char, 32> text{};
  const std::to_chars_result result = std::to_chars(text.data(), text.data() + text.size(), value);
  out.append(text.data(), result.ptr);
}

void appendUnsigned(std::string& out, std::uint64_t value) {
  std::array<char, 24> text{};
  const std::to_chars_result result = std::to_chars(text.data(), text.data() + text.size(), value);
  out.append(text.data(), result.ptr);
}

void flushBuffer(std::string& buffer, std::ostream& out, bool force) {
  if (!force && buffer.size() < kFlushThreshold) return;
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  buffer.clear();
  if (!out) throw RuntimeFailure("write error while writing a mesh (disk full?)");
}

}  // namespace d2vdb::detail
