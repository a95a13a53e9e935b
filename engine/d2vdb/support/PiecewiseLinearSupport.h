// Piecewise-linear support functions on a spherical triangulation and their dual polyhedra
// (Gravesen, Juettler, Sir, "Approximating offsets of surfaces by using the support function
// representation", 2008, section 3, "Approximation by piecewise linear functions").
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"
#include "d2vdb/support/SphericalTriangulation.h"
#include "d2vdb/support/SupportFunction.h"

namespace d2vdb {

/// A support function given by its values h_i at the vertices n_i of a spherical triangulation
/// and linear (in the homogeneous sense) on each triangle: there it is v_t . n, where v_t is the
/// point in which the three planes x . n_i = h_i of the triangle's corners meet. Its surface is the
/// dual polyhedron: one planar face per vertex i (in the plane x . n_i = h_i, bounded by the
/// points v_t of the triangles around i), one vertex v_t per triangle. Offsetting (h_i + d) moves
/// every face plane by exactly d along its normal: the offsets of the polyhedron are exact.
class PiecewiseLinearSupport {
 public:
  /// Throws InputError for an invalid triangulation (validateSphericalTriangulation), a value
  /// count different from the vertex count, or a non-finite value.
  PiecewiseLinearSupport(SphericalTriangulation triangulation, std::vector<double> values);

  /// Samples `h` at the vertices of `triangulation`.
  static PiecewiseLinearSupport sample(const std::function<double(const Eigen::Vector3d&)>& h,
                                       SphericalTriangulation triangulation);

  const SphericalTriangulation& triangulation() const { return triangulation_; }
  const std::vector<double>& values() const { return values_; }

  /// h_i + distance at every vertex. Throws InputError for a non-finite distance.
  PiecewiseLinearSupport offset(double distance) const;

  /// The point where the planes of triangle t's corners meet (Cramer's rule in cross-product
  /// form). Throws InputError when the three normals are linearly dependent (|det| < 1e-14).
  Eigen::Vector3d dualVertex(std::size_t triangle) const;
  /// dualVertex() of every triangle, in triangle order.
  std::vector<Eigen::Vector3d> dualVertices() const;

  /// The dual polyhedron as a triangle mesh: vertex t = dualVertex(t); each vertex i of the
  /// triangulation whose triangles close around it contributes its face, the polygon of the
  /// dual vertices of those triangles in counter-clockwise order about n_i, fanned from its first
  /// corner (so a triangulation of the whole sphere gives a closed polyhedron; on a patch only the
  /// faces of interior vertices appear). No normals.
  TriangleMesh dualPolyhedron() const;

  /// Number of interior edges that fold the polyhedron ("swallowtails"): for the edge (i, j)
  /// between triangles (i, j, k) and (j, i, l), the dual vertex of (i, j, k) lies strictly beyond
  /// the plane x . n_l = h_l (by more than 1e-12 of the largest |h_i|). A polyhedron with no folded
  /// edge is locally convex at every edge; over the whole sphere it is then the convex polyhedron
  /// bounded by all the planes.
  std::size_t foldedEdges() const;

  /// Removes swallowtails by edge flips (Lawson's algorithm on the planes): every folded edge
  /// (i, j) is replaced by (k, l) when both new triangles are counter-clockwise on the sphere and
  /// (k, l) is not already an edge, until no folded edge can be flipped. For the samples of a
  /// convex surface this ends with foldedEdges() == 0. Defined for convex data (all h_i of one
  /// closed convex surface or an elliptic patch); the dual of a saddle-shaped patch has no such
  /// local criterion and is left alone by the caller. Returns the number of flips.
  std::size_t removeSwallowtails();

 private:
  SphericalTriangulation triangulation_;
  std::vector<double> values_;
};

}  // namespace d2vdb
