// Stanford PLY polygon files in their three encodings: ascii, binary_little_endian and
// binary_big_endian.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::detail {

/// How the body of a PLY file is encoded.
enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

/// Parses a PLY file held in memory. The header must start with "ply" and declare format 1.0 in
/// one of the three encodings. The `vertex` element must have scalar properties x, y, z (any
/// numeric type) and may have nx, ny, nz (taken as the normals when all three are present); the
/// `face` element must have a list property `vertex_indices` (or `vertex_index`). Every other
/// property and element, of any PLY type or type alias (char/int8 ... double/float64, and lists),
/// is read and skipped; comments and obj_info lines are ignored. Polygons with more than three
/// corners become a fan of triangles around their first corner; a file without a face element
/// gives a mesh without triangles. In ASCII bodies each element record is one line.
/// Throws InputError "<nameForMessages>, line <n>: ..." (header and ASCII body) or
/// "<nameForMessages>, byte <offset>: ..." (binary body) for anything malformed: a missing or
/// malformed header, no vertices, an unknown type, data that ends early or continues after the
/// declared elements, a non-numeric, NaN/Inf or out-of-range value, a face with fewer than three
/// corners or an index that is negative or not below the vertex count.
TriangleMesh parsePly(std::string_view contents, const std::string& nameForMessages);

/// Reads the rest of `in` (opened in binary mode) and parses it with parsePly.
TriangleMesh readPly(std::istream& in, const std::string& nameForMessages);

/// Writes `mesh` as PLY in `encoding`: float x y z (and nx ny nz when the mesh has normals) and a
/// face list of uchar count and uint indices. ASCII coordinates use the shortest text that reads
/// back exactly. `attributes` (optional) add a float scalar property and uchar red, green, blue
/// after them. Throws InputError (before writing anything) when the mesh cannot be written
/// (see writeMesh) and RuntimeFailure when the stream fails.
void writePly(std::ostream& out, const TriangleMesh& mesh, PlyEncoding encoding,
              const VertexAttributes* attributes = nullptr);

}  // namespace d2vdb::detail
