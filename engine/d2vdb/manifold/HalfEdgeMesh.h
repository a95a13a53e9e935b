// Half-edge adjacency of a closed, 2-manifold, consistently oriented triangle mesh: the
// combinatorial structure the smooth-surface construction walks (vertex rings, edge twins).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// A point of a mesh face: the face index and barycentric coordinates (b0, b1, b2) with respect
/// to the face's corners 0, 1, 2 in the order of TriangleMesh::triangles. Points of the face have
/// b_i >= 0 and b0 + b1 + b2 = 1.
struct FacePoint {
  std::uint32_t face = 0;
  Eigen::Vector3d bary = Eigen::Vector3d(1.0, 0.0, 0.0);
};

/// Half-edge adjacency over a closed triangle mesh in which every edge is shared by exactly two
/// triangles traversing it in opposite directions and every vertex's triangles form one fan
/// (a disc). Half-edge h = 3 f + k of face f runs from corner k to corner (k + 1) % 3, so faces
/// keep the indices and corner order of the input. Each vertex's outgoing half-edges are listed
/// counter-clockwise seen from outside (ring(v, k + 1) = twin(prev(ring(v, k)))), starting with the
/// outgoing half-edge of smallest index; the face of ring(v, k) is the k-th face around v.
///
/// Vertices that no triangle uses are kept (so indices match the input) with degree 0.
/// Immutable after construction; all members are thread-safe.
class HalfEdgeMesh {
 public:
  using Index = std::uint32_t;

  /// Builds the adjacency of `mesh` (positions converted to double). Throws InputError when the
  /// mesh has no triangles, a triangle repeats a vertex or indexes a missing one, an edge is a
  /// boundary edge or is shared by more than two triangles or by two triangles wound alike, a
  /// vertex's triangles form more than one fan, or a vertex has fewer than three neighbours. The
  /// message summarises the mesh's validation report (validateMesh) and names the first offending
  /// edges or vertices by their indices.
  explicit HalfEdgeMesh(const TriangleMesh& mesh);

  /// Same, from double positions (used where round-off of float positions would matter, e.g.
  /// affine images of a mesh). Throws InputError also for non-finite positions.
  HalfEdgeMesh(std::vector<Eigen::Vector3d> positions,
               std::vector<TriangleMesh::Triangle> triangles);

  std::size_t vertexCount() const { return positions_.size(); }
  std::size_t faceCount() const { return triangles_.size(); }
  std::size_t halfEdgeCount() const { return 3 * triangles_.size(); }

  const std::vector<Eigen::Vector3d>& positions() const { return positions_; }
  const Eigen::Vector3d& position(Index vertex) const { return positions_[vertex]; }
  const std::vector<TriangleMesh::Triangle>& triangles() const { return triangles_; }
  /// Corner k (0..2) of `face`.
  Index corner(Index face, int k) const { return triangles_[face][k]; }

  /// Start and end vertex of a half-edge, its face, the next and previous half-edge of that face,
  /// and the opposite half-edge of the neighbouring face.
  Index from(Index halfEdge) const { return triangles_[halfEdge / 3][halfEdge % 3]; }
  Index to(Index halfEdge) const { return triangles_[halfEdge / 3][(halfEdge % 3 + 1) % 3]; }
  static Index face(Index halfEdge) { return halfEdge / 3; }
  static Index next(Index halfEdge) { return halfEdge - halfEdge % 3 + (halfEdge % 3 + 1) % 3; }
  static Index prev(Index halfEdge) { return halfEdge - halfEdge % 3 + (halfEdge % 3 + 2) % 3; }
  Index twin(Index halfEdge) const { return twin_[halfEdge]; }

  /// Number of edges at `vertex` (0 for an unused vertex).
  int degree(Index vertex) const {
    return static_cast<int>(ringStart_[vertex + 1] - ringStart_[vertex]);
  }
  /// The k-th outgoing half-edge of `vertex` counter-clockwise, k taken modulo degree(vertex).
  Index ring(Index vertex, int k) const {
    const int n = degree(vertex);
    return ring_[ringStart_[vertex] + static_cast<std::size_t>(((k % n) + n) % n)];
  }
  /// Position of outgoing half-edge `halfEdge` in the ring of from(halfEdge).
  int ringIndex(Index halfEdge) const { return ringIndex_[halfEdge]; }
  /// Largest vertex degree.
  int maxDegree() const { return maxDegree_; }

  /// Diagonal length of the bounding box of the used vertices.
  double boundingBoxDiagonal() const { return diagonal_; }

 private:
  void build();

  std::vector<Eigen::Vector3d> positions_;
  std::vector<TriangleMesh::Triangle> triangles_;
  std::vector<Index> twin_;
  std::vector<std::size_t> ringStart_;
  std::vector<Index> ring_;
  std::vector<int> ringIndex_;
  int maxDegree_ = 0;
  double diagonal_ = 0.0;
};

}  // namespace d2vdb
