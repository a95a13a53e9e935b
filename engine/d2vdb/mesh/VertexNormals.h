// Per-vertex normals computed from a mesh's triangles.
#pragma once

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// Replaces mesh.normals with one unit normal per vertex: the sum of the right-hand normals of the
/// triangles around the vertex, each weighted by its area (computed in double precision), then
/// normalised. Vertices whose triangles all have zero area (or that no triangle uses) get (0, 0,
/// 1). Throws InputError, leaving the mesh unchanged, if a triangle references a missing vertex.
void computeVertexNormals(TriangleMesh& mesh);

}  // namespace d2vdb
