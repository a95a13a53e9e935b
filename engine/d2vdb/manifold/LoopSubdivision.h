// One step of Loop subdivision over a closed triangle mesh.
#pragma once

#include "d2vdb/manifold/HalfEdgeMesh.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// One step of Loop subdivision (Loop, "Smooth subdivision surfaces based on triangles", M.S.
/// thesis, University of Utah, 1987): vertex v of degree N moves to (1 - N beta) v + beta (sum of
/// its neighbours), beta = (5/8 - (3/8 + cos(2 pi / N) / 4)^2) / N; each edge gets the point
/// 3/8 (its ends) + 1/8 (the two opposite vertices). Vertex indices: the input's vertices first
/// (same indices), then one per edge in the order of the edge's smaller half-edge index. Face f
/// (a, b, c) becomes faces 4f..4f+3: (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca), so
/// orientation is kept. Parallel (TBB), deterministic. Throws InputError only if the result would
/// exceed 32-bit indices.
HalfEdgeMesh loopSubdivision(const HalfEdgeMesh& mesh);

/// The mesh as an indexed TriangleMesh (positions rounded to float, no normals).
TriangleMesh toTriangleMesh(const HalfEdgeMesh& mesh);

}  // namespace d2vdb
