// The integer winding number of a watertight triangle mesh by counting signed ray crossings with
// certified orientation predicates.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "d2vdb/mesh/TriangleBvh.h"

namespace d2vdb::detail {

/// Sign of the orientation determinant det[a - d, b - d, c - d] (positive when d lies behind the
/// triangle (a, b, c), i.e. on the side away from its normal (b - a) x (c - a)), certified with
/// a static forward error bound for double arithmetic (Shewchuk, "Adaptive precision
/// floating-point arithmetic and fast robust geometric predicates", Discrete & Computational
/// Geometry 18, 1997): +1 or -1 when the computed sign is certainly right, 0 when rounding
/// leaves it in doubt (including exact zeros).
int certifiedOrientation(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c, const Eigen::Vector3d& d);

/// For a watertight mesh (every edge traversed equally often each way), its winding number W at
/// `q` is an integer off the surface and equals the signed number of times a ray from q crosses
/// it: +1 for each triangle the ray leaves through its front (q behind the triangle), -1 for
/// each it enters. Casts rays from q in a fixed sequence of directions; a ray is used only when
/// every predicate of every triangle it might touch is certain (certifiedOrientation()), so a ray
/// through an edge, a vertex or a triangle's plane is discarded. Returns W, or nothing when every
/// direction left a doubt (then use the hierarchical evaluation). Each ray is a segment ending
/// well outside the box of `bvh`, which must be built over `points` and `triangles`. Thread-safe;
/// the same query gives the same answer on any thread.
std::optional<long> rayWindingNumber(const TriangleBvh& bvh,
                                     const std::vector<Eigen::Vector3d>& points,
                                     const std::vector<TriangleIndices>& triangles,
                                     const Eigen::Vector3d& q);

}  // namespace d2vdb::detail
