// Triangle meshes of support-function surfaces and their offsets.
#pragma once

#include "d2vdb/mesh/TriangleMesh.h"
#include "d2vdb/support/SphericalTriangulation.h"
#include "d2vdb/support/SupportFunction.h"

namespace d2vdb {

/// The offset surface at signed distance `offset` over `domain`, as a triangle mesh: vertex i is
/// x_{h+offset}(n_i) = x_h(n_i) + offset n_i with the unit normal n_i (exactly the surface normal
/// there), and the domain's triangles, reversed where the offset surface's Gauss map reverses
/// orientation (det(Hess_S h + (h + offset) I) < 0 at all three corners, e.g. saddle patches) so
/// that every triangle's right-hand normal agrees with the vertex normals. Over the whole sphere
/// of a regular convex h this is a closed, 2-manifold, outward-oriented mesh. Positions are
/// rounded to float (TriangleMesh). Evaluation is parallel; the result does not depend on the
/// thread count. Throws InputError for an invalid domain or a non-finite offset.
TriangleMesh tessellateSupport(const SupportFunction& h, SphericalTriangulation domain,
                               double offset = 0.0);

}  // namespace d2vdb
