// Reading and writing point sets: .xyz text files and the vertices of .ply files.
#pragma once

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

// d2vdb point files
// =================
// .xyz (text): one point per line, "x y z" separated by spaces or tabs; further columns on a line
// (normals, colours, ...) are ignored; '#' starts a comment that runs to the end of the line;
// blank lines are skipped; LF or CRLF line ends. Numbers are decimal (C locale, a leading '+'
// accepted). Every coordinate must be finite.
// .ply: the vertex element of any PLY file d2vdb's mesh reader accepts (PlyFormat.h: ascii and
// binary, extra properties skipped); faces, when present, are ignored. PLY coordinates pass
// through that reader's 32-bit floats.
// Errors: InputError naming the file and the line (text) or byte offset (binary PLY).

namespace d2vdb {

/// Reads the points of a .xyz or .ply file (extension in any letter case), in file order.
/// Throws InputError naming the file for a missing or unreadable file, an unsupported extension,
/// a line with fewer than three numbers or a token that is not a number, a NaN, infinite or
/// out-of-range coordinate (with the line), and a file without any point.
std::vector<Eigen::Vector3d> readPointSet(const std::filesystem::path& file);

/// Parses .xyz text; `sourceName` stands for the file name in messages. Failure behaviour as
/// readPointSet().
std::vector<Eigen::Vector3d> parseXyz(std::string_view text,
                                      const std::string& sourceName = "<string>");

/// The points as .xyz text: "x y z" per line, each coordinate with 17 significant digits (reads
/// back bit for bit). Throws InputError for an empty set or a non-finite coordinate.
std::string pointSetToXyz(const std::vector<Eigen::Vector3d>& points);

/// Writes pointSetToXyz(points) to `file`, which must end in .xyz, atomically. Throws InputError
/// (before writing) for another extension, an empty set or a non-finite coordinate, and
/// RuntimeFailure when the file cannot be written (an existing file is then left unchanged).
void writePointSet(const std::filesystem::path& file, const std::vector<Eigen::Vector3d>& points);

}  // namespace d2vdb
