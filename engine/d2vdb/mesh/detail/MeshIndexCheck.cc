#include "d2vdb/mesh/detail/MeshIndexCheck.h"

#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {

void checkTriangleIndices(const TriangleMesh& mesh, const char* operation) {
  const std::size_t vertexCount = mesh.positions.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const TriangleMesh::Index index : mesh.triangles[t]) {
      if (index >= vertexCount) {
        throw InputError(std::string(operation) + ": triangle " + std::to_string(t) +
                         " references vertex " + std::to_string(index) +
                         ", but the mesh has only " + std::to_string(vertexCount) + " vertices");
      }
    }
  }
}

}  // namespace d2vdb::detail
