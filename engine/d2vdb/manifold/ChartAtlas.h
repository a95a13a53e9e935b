// The p-domains (charts) of a parametric pseudo-manifold and the transition maps between them.
#pragma once

#include <Eigen/Core>

#include <optional>

#include "d2vdb/manifold/HalfEdgeMesh.h"

namespace d2vdb {

/// A point of the chart (p-domain) of a mesh vertex, in the chart's own plane coordinates.
struct ChartPoint {
  HalfEdgeMesh::Index vertex = 0;
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
};

/// The charts of a parametric pseudo-manifold over a closed mesh (Siqueira, Xu, Gallier, Nonato,
/// Morera, Velho, "A new construction of smooth surfaces from triangle meshes using parametric
/// pseudo-manifolds", Computers & Graphics 33(3), 2009).
///
/// The chart of a vertex v of degree n is the open disc of radius cos(pi / n) centred at the
/// origin: the disc inscribed in the regular n-gon with corners exp(2 pi i k / n). Sector k of the
/// n-gon (between the rays at angles 2 pi k / n and 2 pi (k + 1) / n) stands for the face of the
/// k-th outgoing half-edge of v (HalfEdgeMesh::ring). A point of a face is related to the chart
/// of its corner v through the face's canonical equilateral triangle (v at 0, the next corner at
/// 1, the one after at exp(i pi / 3)): the point with barycentric coordinates (b_v, b_next,
/// b_after) is z = b_next + b_after exp(i pi / 3), and its chart point has polar coordinates
///
///   radius = |z| cos(pi / n) / cos(pi / 6),   angle = arg(z) 6 / n + 2 pi k / n
///
/// for the face's sector k. The chart disc therefore covers exactly the points at distance
/// < sqrt(3) / 2 from v in the canonical triangles of v's faces. Polar angles are taken with a
/// signed atan2, never by quadrant from acos/asin, so the maps are continuous across every sector
/// boundary for any degree >= 3.
///
/// Transition maps: the chart of u and the chart of a neighbour v overlap on the points of the
/// two faces at the edge uv that both discs contain. The transition from u to v rotates the edge
/// uv onto the positive axis, maps to the regular hexagon (angle * n_u / 6, radius * cos(pi / 6)
/// / cos(pi / n_u)), turns the hexagon of u into the hexagon of v by z -> 1 - z (a half turn about
/// the edge midpoint, which keeps the orientation), and applies the inverse map of v. These maps
/// are exact compositions of rigid motions and polar rescalings, so transitions compose:
/// g_wu = g_wv o g_vu wherever the three charts overlap (up to round-off).
///
/// The atlas only reads the mesh it was given (which must outlive it). Thread-safe.
class ChartAtlas {
 public:
  explicit ChartAtlas(const HalfEdgeMesh& mesh) : mesh_(&mesh) {}

  const HalfEdgeMesh& mesh() const { return *mesh_; }

  /// The chart radius cos(pi / n) of a vertex of degree n (>= 3).
  static double radius(int degree);

  /// The point of `face` at `bary` in the canonical triangle of its corner `corner` (0..2):
  /// z = b_next + b_after exp(i pi / 3), as (Re z, Im z).
  static Eigen::Vector2d canonical(const Eigen::Vector3d& bary, int corner);

  /// Whether the point lies in the chart of the face's corner `corner`: |canonical| <
  /// cos(pi / 6).
  static bool inChart(const Eigen::Vector3d& bary, int corner);

  /// The chart point of corner `corner` of `point.face` (any barycentric coordinates of the face
  /// may be given; the map is defined for points of the face). The result lies in the open chart
  /// disc exactly when inChart() holds.
  ChartPoint toChart(const FacePoint& point, int corner) const;

  /// The face point of a chart point with |p| < radius(degree(vertex)) (the open disc): the face of
  /// the sector that contains p and the barycentric coordinates there (a point on a sector
  /// boundary goes to the face counter-clockwise from it). Throws InputError outside the disc
  /// or for a vertex that no face uses.
  FacePoint fromChart(const ChartPoint& point) const;

  /// The transition map from the chart of from(halfEdge) = u to the chart of to(halfEdge) = v at
  /// p: nothing when p is not in the overlap (outside the disc of u, outside the two sectors at
  /// the edge, or mapped outside the disc of v).
  std::optional<Eigen::Vector2d> transition(HalfEdgeMesh::Index halfEdge,
                                            const Eigen::Vector2d& p) const;

 private:
  const HalfEdgeMesh* mesh_;
};

}  // namespace d2vdb
