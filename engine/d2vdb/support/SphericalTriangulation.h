// Triangulations of (parts of) the unit sphere of normals: the domains of support functions.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace d2vdb {

/// A triangulation of the whole unit sphere or of a region of it (a patch's Gauss image).
/// `normals` are unit vectors; `triangles` index them and are wound counter-clockwise seen from
/// outside the sphere (det(n_a, n_b, n_c) > 0 for a triangle smaller than a hemisphere).
struct SphericalTriangulation {
  using Index = std::uint32_t;
  using Triangle = std::array<Index, 3>;

  std::vector<Eigen::Vector3d> normals;
  std::vector<Triangle> triangles;
};

/// The geodesic sphere: an icosahedron whose triangles are split into four `subdivisions` times,
/// new vertices projected onto the sphere. 10 * 4^s + 2 vertices, 20 * 4^s triangles, longest
/// edge about 1.1 / 2^s radians. Deterministic (vertex order: the icosahedron's, then edge
/// midpoints in order of creation). Throws InputError for subdivisions outside 0..9.
SphericalTriangulation geodesicSphere(int subdivisions);

/// The smallest geodesic-sphere subdivision whose longest edge is at most `angle` radians (capped
/// at 9). Throws InputError for a non-positive or non-finite angle.
int geodesicSubdivisionsForSpacing(double angle);

/// Checks that `domain` is usable: at least one triangle, every normal finite and unit to within
/// 1e-9 (the normals are renormalised when only rounding separates them from unit length), every
/// index in range, no triangle with repeated corners. Throws InputError naming `what` and the
/// offending normal or triangle.
void validateSphericalTriangulation(SphericalTriangulation& domain, const std::string& what);

/// Whether `domain` covers the whole sphere: every undirected edge is shared by exactly two
/// triangles and the Euler characteristic V - E + F is 2.
bool coversWholeSphere(const SphericalTriangulation& domain);

/// Unit vector in the direction of `vector`. Throws InputError naming `what` when `vector` is
/// zero, not finite, or so small that normalising it loses precision.
Eigen::Vector3d unitNormalOrThrow(const Eigen::Vector3d& vector, const std::string& what);

}  // namespace d2vdb
