// Joining test meshes: one mesh's triangles and vertices appended to another's.
#pragma once

#include <utility>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::test {

/// Appends `part` to `mesh`, renumbering its vertices after the existing ones; with
/// `reverseWinding` every appended triangle is wound the other way (an inward shell).
inline void append(TriangleMesh& mesh, const TriangleMesh& part, bool reverseWinding = false) {
  const auto base = static_cast<TriangleMesh::Index>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
  for (TriangleMesh::Triangle triangle : part.triangles) {
    for (TriangleMesh::Index& corner : triangle) corner += base;
    if (reverseWinding) std::swap(triangle[1], triangle[2]);
    mesh.triangles.push_back(triangle);
  }
}

}  // namespace d2vdb::test
