// Reading and writing triangle meshes as OBJ, PLY and STL files, chosen by file extension.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// The mesh file formats d2vdb reads and writes.
enum class MeshFormat { Obj, Ply, Stl };

/// The format named by the extension of `path` (".obj", ".ply", ".stl", any letter case).
/// Throws InputError naming the extension (or its absence) and the supported ones otherwise.
MeshFormat meshFormatFromPath(const std::filesystem::path& path);

/// The usual name of a format: "OBJ", "PLY" or "STL".
std::string meshFormatName(MeshFormat format);

/// Reads the mesh in `path`, choosing the reader by extension (see ObjFormat.h, PlyFormat.h and
/// StlFormat.h for what each accepts; an STL file is recognised as ASCII or binary from its
/// content). The result always has in-range indices and finite coordinates; normals are filled
/// when the file gives one per vertex. Throws InputError naming the file for an unsupported
/// extension, a missing or unreadable file, and malformed content (with the line or byte offset).
TriangleMesh readMesh(const std::filesystem::path& path);

/// Reads the mesh in `path` as `format` whatever its extension (for callers that recognised the
/// format from the content, such as loadInput() in io/InputFile.h). Failure behaviour as above.
TriangleMesh readMesh(const std::filesystem::path& path, MeshFormat format);

/// How writeMesh encodes the formats that have both text and binary variants.
struct MeshWriteOptions {
  bool binary = true;      ///< PLY and STL: binary (default) or ASCII; OBJ is always text
  bool bigEndian = false;  ///< binary PLY only: binary_big_endian instead of binary_little_endian
};

/// Optional per-vertex data written beside the positions. PLY: the scalar as "property float
/// <scalarName>" and the colours as "property uchar red/green/blue" (MeshLab, Blender and Houdini
/// read both); OBJ: the colours as "v x y z r g b" with r, g, b in [0, 1] (the common extension
/// MeshLab and Blender read), no scalar; STL: neither. Each list is empty (not written) or holds
/// one entry per vertex.
struct VertexAttributes {
  std::string scalarName;                           ///< e.g. "distance"; a PLY identifier
  std::vector<float> scalars;                       ///< one per vertex, finite
  std::vector<std::array<std::uint8_t, 3>> colors;  ///< RGB, one per vertex
  /// Further named scalars (PLY only, as "property float <name>" after the scalar above, in this
  /// order; OBJ and STL leave them out): names are PLY identifiers distinct from each other,
  /// from scalarName and from x, y, z, nx, ny, nz, red, green, blue; one finite value per vertex.
  std::vector<std::pair<std::string, std::vector<float>>> moreScalars;
};

/// Writes `mesh` to `path` in the format of its extension, atomically (a failure leaves an existing
/// file untouched). Coordinates are written so that they read back bit for bit; per-vertex normals
/// are written to OBJ and PLY when the mesh has them, STL gets facet normals computed from the
/// triangles. Throws InputError for an unsupported extension or a mesh that cannot be written
/// (no vertices, an index out of range, a non-finite coordinate) and RuntimeFailure when the file
/// cannot be written.
void writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh,
               const MeshWriteOptions& options = {});

/// writeMesh() with per-vertex attributes. InputError as writeMesh(), and for attribute lists
/// whose size is not the vertex count, a non-finite scalar, or a scalar name that is empty or not
/// a plain identifier (letters, digits, '_') while scalars are given, or repeats another name.
void writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh,
               const VertexAttributes& attributes, const MeshWriteOptions& options = {});

/// What a mesh file holds besides positions and triangles, for estimateMeshFileBytes().
struct MeshFileContents {
  bool normals = false;  ///< per-vertex normals (OBJ, PLY; STL always has facet normals)
  bool colors = false;   ///< per-vertex RGB (OBJ, PLY)
  int scalars = 0;       ///< per-vertex float properties (PLY only)
};

/// An upper bound on the bytes writeMesh() writes for a mesh of `vertices` vertices and
/// `triangles` triangles with `contents`, before the mesh exists (for the output budget,
/// core/ResourceBudget.h). Binary encodings are exact up to the header; text encodings count
/// every coordinate at its longest shortest-round-trip form (15 characters) and every index at
/// the digits of the largest one, so they stay within 1.5 times the real size for coordinates of
/// order one (tests/mesh/MeshFileEstimateTest.cc). Doubles, so that absurd requests do not
/// overflow.
double estimateMeshFileBytes(MeshFormat format, double vertices, double triangles,
                             const MeshFileContents& contents,
                             const MeshWriteOptions& options = {});

}  // namespace d2vdb
