// Curved PN triangles: a cubic Bézier triangle per face from vertex positions and normals.
#pragma once

#include <Eigen/Core>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "d2vdb/manifold/SourceSurface.h"

namespace d2vdb {

/// The PN triangle surface of Vlachos, Peters, Boyd, Mitchell, "Curved PN triangles" (ACM
/// Symposium on Interactive 3D Graphics, 2001, section 3.1): over each face a cubic Bézier
/// triangle with the corners b300, b030, b003 at the vertices, the edge points
/// b210 = (2 P1 + P2 - w12 N1) / 3 (w_ij = (P_j - P_i) . N_i; likewise for the other five), and
/// the centre b111 = E + (E - V) / 2 with E the mean of the six edge points and V of the three
/// corners. Edge points depend only on the edge's two vertices and their normals, so patches meet
/// continuously (C0; the surface is not tangent-continuous across edges in general).
class PnTriangles final : public SourceSurface {
 public:
  /// PN triangles over `mesh` with one unit normal per vertex (`normals[v]`). Throws InputError
  /// for a null mesh, a normal count that differs from the vertex count, or a used vertex whose
  /// normal is not finite or not of unit length (|n| - 1 beyond 1e-6).
  PnTriangles(std::shared_ptr<const HalfEdgeMesh> mesh, std::vector<Eigen::Vector3d> normals);

  /// PN triangles with the area-weighted mean of the faces' normals at each vertex. Throws
  /// InputError for a null mesh or a vertex whose faces have no area.
  explicit PnTriangles(std::shared_ptr<const HalfEdgeMesh> mesh);

  const HalfEdgeMesh& mesh() const override { return *mesh_; }
  std::shared_ptr<const HalfEdgeMesh> sharedMesh() const override { return mesh_; }
  void positions(HalfEdgeMesh::Index face, const Eigen::Vector3d* bary, std::size_t count,
                 Eigen::Vector3d* out) const override;
  SourceJet evaluate(const FacePoint& point) const override;
  std::string name() const override { return "pn"; }

  /// The vertex normals in use.
  const std::vector<Eigen::Vector3d>& normals() const { return normals_; }
  /// The ten control points of a face's cubic patch (TriangleBezier layout: b_{ijk} with j, k the
  /// exponents of b1, b2).
  std::array<Eigen::Vector3d, 10> controlNet(HalfEdgeMesh::Index face) const;

 private:
  std::shared_ptr<const HalfEdgeMesh> mesh_;
  std::vector<Eigen::Vector3d> normals_;
};

}  // namespace d2vdb
