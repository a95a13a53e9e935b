// Which triangles of a mesh meet others (whether the mesh intersects itself).
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/mesh/TriangleBvh.h"

namespace d2vdb::detail {

/// Per triangle: whether it meets another triangle anywhere but in the corners or the edge they
/// share (by index): crossing or touching triangles, overlapping coplanar ones, an edge folded
/// flat onto its neighbour, two triangles on the same three corners. Conservative:
/// configurations closer than `tolerance` (absolute, in the points' units) to touching count as
/// intersecting, so that rounding can only ever add an intersection, never hide one. Triangles
/// marked `degenerate` are left out (they enclose nothing). Parallel (TBB) over the BVH's leaves,
/// each tested against the leaves whose boxes overlap its own, then triangle boxes, then the
/// pairwise test below; the answer does not depend on the thread count.
std::vector<bool> selfIntersectingTriangles(const std::vector<Eigen::Vector3d>& points,
                                            const std::vector<TriangleIndices>& triangles,
                                            const std::vector<bool>& degenerate,
                                            const TriangleBvh& bvh, double tolerance);

/// The pairwise test used above, exposed for tests: triangles given by corner positions and
/// indices (shared indices mean shared corners).
bool trianglesIntersect(const std::vector<Eigen::Vector3d>& points, const TriangleIndices& first,
                        const TriangleIndices& second, double tolerance);

}  // namespace d2vdb::detail
