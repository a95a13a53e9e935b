#include "d2vdb/manifold/LoopSubdivision.h"

#include <tbb/parallel_for.h>

#include <limits>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/detail/LoopPatches.h"

namespace d2vdb {

using Index = HalfEdgeMesh::Index;

HalfEdgeMesh loopSubdivision(const HalfEdgeMesh& mesh) {
  const std::size_t vertexCount = mesh.vertexCount();
  const std::size_t halfEdges = mesh.halfEdgeCount();
  const std::size_t edgeCount = halfEdges / 2;
  if (vertexCount + edgeCount > std::numeric_limits<Index>::max() ||
      4 * mesh.faceCount() > (std::numeric_limits<Index>::max() - 3) / 3) {
    throw InputError("one Loop subdivision step of a mesh with " +
                     std::to_string(mesh.faceCount()) + " triangles would exceed 32-bit indices");
  }
  // Edge numbers in the order of each edge's smaller half-edge.
  std::vector<Index> edgeOf(halfEdges);
  std::vector<Index> edgeHalf;
  edgeHalf.reserve(edgeCount);
  for (Index h = 0; h < halfEdges; ++h) {
    if (h < mesh.twin(h)) {
      edgeOf[h] = static_cast<Index>(edgeHalf.size());
      edgeOf[mesh.twin(h)] = edgeOf[h];
      edgeHalf.push_back(h);
    }
  }
  std::vector<Eigen::Vector3d> positions(vertexCount + edgeHalf.size());
  tbb::parallel_for(std::size_t{0}, vertexCount, [&](std::size_t v) {
    const auto vertex = static_cast<Index>(v);
    const int n = mesh.degree(vertex);
    if (n == 0) {
      positions[v] = mesh.position(vertex);
      return;
    }
    const double beta = detail::loopBeta(n);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < n; ++k) sum += mesh.position(mesh.to(mesh.ring(vertex, k)));
    positions[v] = (1.0 - n * beta) * mesh.position(vertex) + beta * sum;
  });
  tbb::parallel_for(std::size_t{0}, edgeHalf.size(), [&](std::size_t e) {
    const Index h = edgeHalf[e];
    const Index t = mesh.twin(h);
    positions[vertexCount + e] =
        3.0 / 8.0 * (mesh.position(mesh.from(h)) + mesh.position(mesh.to(h))) +
        1.0 / 8.0 *
            (mesh.position(mesh.to(HalfEdgeMesh::next(h))) +
             mesh.position(mesh.to(HalfEdgeMesh::next(t))));
  });
  std::vector<TriangleMesh::Triangle> triangles(4 * mesh.faceCount());
  tbb::parallel_for(std::size_t{0}, mesh.faceCount(), [&](std::size_t f) {
    const auto face = static_cast<Index>(f);
    const Index a = mesh.corner(face, 0);
    const Index b = mesh.corner(face, 1);
    const Index c = mesh.corner(face, 2);
    const auto base = static_cast<Index>(vertexCount);
    const Index ab = base + edgeOf[3 * f];
    const Index bc = base + edgeOf[3 * f + 1];
    const Index ca = base + edgeOf[3 * f + 2];
    triangles[4 * f + 0] = {a, ab, ca};
    triangles[4 * f + 1] = {ab, b, bc};
    triangles[4 * f + 2] = {ca, bc, c};
    triangles[4 * f + 3] = {ab, bc, ca};
  });
  return HalfEdgeMesh(std::move(positions), std::move(triangles));
}

TriangleMesh toTriangleMesh(const HalfEdgeMesh& mesh) {
  TriangleMesh result;
  result.positions.reserve(mesh.vertexCount());
  for (const Eigen::Vector3d& p : mesh.positions()) result.positions.push_back(p.cast<float>());
  result.triangles = mesh.triangles();
  return result;
}

}  // namespace d2vdb
