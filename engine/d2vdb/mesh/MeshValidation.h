// Topological and geometric sanity report for a triangle mesh.
#pragma once

#include <cstddef>
#include <string>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// What validateMesh() found. Counts are exact; `closed` means every edge is shared by exactly two
/// triangles (no boundary, no non-manifold edge).
struct MeshReport {
  std::size_t vertexCount = 0;
  std::size_t triangleCount = 0;
  std::size_t edgeCount = 0;             ///< distinct undirected edges
  std::size_t boundaryEdgeCount = 0;     ///< edges used by exactly one triangle
  std::size_t nonManifoldEdgeCount = 0;  ///< edges used by three or more triangles
  std::size_t nonManifoldVertexCount =
      0;                              ///< vertices whose triangle fan is not one disc/half-disc
  std::size_t boundaryLoopCount = 0;  ///< closed chains of boundary edges
  std::size_t degenerateTriangleCount =
      0;  ///< repeated index or zero area (|cross| <= 1e-12 * scale)
  std::size_t inconsistentlyOrientedEdgeCount =
      0;  ///< manifold edges both triangles traverse alike
  std::size_t unreferencedVertexCount = 0;
  std::size_t connectedComponentCount = 0;  ///< over triangles sharing an edge
  bool closed = false;    ///< no boundary edges, no non-manifold edges, at least one triangle
  bool manifold = false;  ///< no non-manifold edges or vertices
  bool oriented = false;  ///< consistently oriented (no inconsistently oriented edges)
  long eulerCharacteristic = 0;  ///< V - E + F over referenced vertices

  /// One line per problem found, e.g. "12 boundary edges in 2 loops (the mesh is not closed)";
  /// empty when the mesh is closed, manifold, oriented and has no degenerate triangles.
  std::string problems() const;
};

/// Computes the report. O(V + F log F); never throws on index-valid meshes, throws InputError if a
/// triangle references a vertex that does not exist.
/// Triangles with a repeated index count as degenerate and take no further part: they add no
/// edges, fans, boundary loops or components, and are not counted in F of the Euler
/// characteristic (V counts every vertex some triangle references). Where non-manifold edges
/// make the chaining of boundary edges ambiguous, an open chain counts as one loop.
MeshReport validateMesh(const TriangleMesh& mesh);

}  // namespace d2vdb
