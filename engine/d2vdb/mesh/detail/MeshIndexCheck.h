// Checking that a mesh's triangles only reference existing vertices. Internal to the mesh module.
#pragma once

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::detail {

/// Throws InputError "<operation>: triangle T references vertex I, but the mesh has only N
/// vertices" for the first triangle with an index out of range; returns normally otherwise.
void checkTriangleIndices(const TriangleMesh& mesh, const char* operation);

}  // namespace d2vdb::detail
