// Pieces shared by the mesh file readers and writers: located error messages, loading a file or
// stream into memory, checking a mesh before writing it, and exact text output of numbers.
// Internal to the mesh module.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <string_view>

#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::detail {

/// Throws InputError "<fileName>: <problem>" (for problems with the file as a whole).
[[noreturn]] void throwInFile(const std::string& fileName, const std::string& problem);

/// Throws InputError "<fileName>, line <lineNumber>: <problem>" (text formats; lines count from 1).
[[noreturn]] void throwAtLine(const std::string& fileName, std::size_t lineNumber,
                              const std::string& problem);

/// Throws InputError "<fileName>, byte <byteOffset>: <problem>" (binary data; offsets from 0).
[[noreturn]] void throwAtByte(const std::string& fileName, std::size_t byteOffset,
                              const std::string& problem);

/// `text` in single quotes for a message, shortened to its first 40 characters.
std::string inQuotes(std::string_view text);

/// The whole content of a file. Throws InputError naming the path when it does not exist, is a
/// directory, or cannot be opened or read.
std::string readFileContents(const std::filesystem::path& path);

/// Everything left in `in`. Throws InputError naming `nameForMessages` when the stream fails.
std::string readStreamContents(std::istream& in, const std::string& nameForMessages);

/// Checks, before anything is written, that `mesh` can be written as `formatName`: at least one
/// vertex, every triangle index in range, every coordinate (and normal, when present) finite.
/// Throws InputError describing the first offending triangle or vertex.
void checkMeshIsWritable(const TriangleMesh& mesh, const char* formatName);

/// Appends the shortest decimal text that reads back as exactly `value` (std::to_chars).
void appendFloat(std::string& out, float value);

/// Throws InputError unless every non-empty attribute list of `attributes` has one entry per
/// vertex of `mesh`, the scalars are finite and, when scalars are given, the scalar name is a
/// plain identifier.
void checkVertexAttributes(const TriangleMesh& mesh, const VertexAttributes& attributes);

/// Appends `value` in decimal.
void appendUnsigned(std::string& out, std::uint64_t value);

/// Writes `buffer` to `out` and clears it once it holds more than about a megabyte (call with
/// force = true at the end). Throws RuntimeFailure when the stream reports an error.
void flushBuffer(std::string& buffer, std::ostream& out, bool force = false);

/// The most vertices a mesh read from a file may have, so that every index fits
/// TriangleMesh::Index.
inline constexpr std::uint64_t kMaxVertexCount = 0xFFFFFFFFull;

}  // namespace d2vdb::detail
