// STL (stereolithography) triangle soups, ASCII and binary, welded into indexed meshes on read.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::detail {

/// How an STL file is encoded.
enum class StlEncoding { Ascii, Binary };

/// The encoding of STL `contents`: binary when it is at least 84 bytes long and its size is exactly
/// 84 + 50 * (the triangle count at byte 80), even if it begins with "solid" as some exporters'
/// binary headers do; otherwise ASCII when it begins with "solid" and holds no NUL byte; otherwise
/// binary (which parseStl then reports as malformed).
StlEncoding detectStlEncoding(std::string_view contents);

/// Parses an STL file held in memory (either encoding, see detectStlEncoding). STL stores every
/// triangle's three corners separately; corners with exactly equal positions (0 and -0 are equal)
/// are welded into one vertex, numbered in order of first occurrence, so the result is an indexed
/// mesh. Facet normals in the file must be finite numbers but are otherwise ignored (the mesh gets
/// no normals). ASCII files may hold
/// several solids; keywords are matched without regard to letter case.
/// Throws InputError "<nameForMessages>, line <n>: ..." (ASCII) or "<nameForMessages>, byte
/// <offset>: ..." (binary) for anything malformed: an empty file, a size that does not match the
/// binary triangle count, no facets at all, an unexpected keyword, a missing `endsolid`, a facet
/// without exactly three vertices, a non-numeric, NaN/Inf or out-of-range vertex coordinate or
/// facet normal component.
TriangleMesh parseStl(std::string_view contents, const std::string& nameForMessages);

/// Reads the rest of `in` (opened in binary mode) and parses it with parseStl.
TriangleMesh readStl(std::istream& in, const std::string& nameForMessages);

/// Writes `mesh` as STL in `encoding`, one facet per triangle with its unit normal computed from
/// the corner positions (the right-hand rule; zero for a degenerate triangle). The binary header
/// does not begin with "solid". ASCII coordinates use the shortest text that reads back exactly.
/// Per-vertex normals are not stored (STL has none). Throws InputError (before writing anything)
/// when the mesh cannot be written (see writeMesh; also no triangles, or more than 2^32-1 in
/// binary) and RuntimeFailure when the stream fails.
void writeStl(std::ostream& out, const TriangleMesh& mesh, StlEncoding encoding);

}  // namespace d2vdb::detail
