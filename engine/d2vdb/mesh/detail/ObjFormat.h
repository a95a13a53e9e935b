// Wavefront OBJ mesh files: the polygon subset (v, vn, f), read and written as text.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::detail {

/// Parses OBJ text. Reads `v x y z` (an optional w and vertex colours after xyz are checked to be
/// numbers and ignored), `vn x y z`, and `f` with corners `i`, `i/t`, `i//n` or `i/t/n`, where
/// indices count from 1 and negative indices count back from the last element defined so far.
/// Polygons with more than three corners become a fan of triangles around their first corner.
/// `vt`, `g`, `o`, `s`, `usemtl`, `mtllib`, lines and points (`l`, `p`), the other display
/// statements, comments and blank lines are ignored; free-form geometry is refused.
/// Normals: a vertex gets the normal its face corners name. When any face corner names no normal,
/// or corners of one vertex name different normals, the normals are dropped (positions and
/// triangles are unaffected); a vertex used by no face takes the normal with its own index.
/// Throws InputError "<nameForMessages>, line <n>: ..." for anything malformed: a missing or
/// non-numeric coordinate, a NaN/Inf or out-of-range coordinate, an index that is 0 or refers to
/// an element that does not exist, a face with fewer than three corners, an unknown statement,
/// and a file without vertices.
TriangleMesh parseObj(std::string_view text, const std::string& nameForMessages);

/// Reads the rest of `in` and parses it with parseObj.
TriangleMesh readObj(std::istream& in, const std::string& nameForMessages);

/// Writes `mesh` as OBJ: `v` lines, `vn` lines when the mesh has normals, and one `f a b c` (or
/// `f a//a b//b c//c`) per triangle. Coordinates use the shortest text that reads back exactly.
/// With attributes holding colours, vertices are written "v x y z r g b" (r, g, b in [0, 1]).
/// Throws InputError (before writing anything) when the mesh cannot be written (see
/// writeMesh) and RuntimeFailure when the stream fails.
void writeObj(std::ostream& out, const TriangleMesh& mesh,
              const VertexAttributes* attributes = nullptr);

}  // namespace d2vdb::detail
