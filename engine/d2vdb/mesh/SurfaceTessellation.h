// Triangulating a B-spline surface on a regular parameter grid.
#pragma once

#include "d2vdb/mesh/TriangleMesh.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

/// Triangulates `surface` on a regular parameter grid with samplesU x samplesV vertices.
///
/// Open direction: parameters domain.at(k / (samples - 1)), both ends included (samples >= 2).
/// Closed direction: parameters domain.at(k / samples), k < samples; the last grid line connects
/// back to the first, so the seam has no duplicate vertices (samples >= 3). A surface closed in
/// both directions therefore gives a closed mesh (a torus topologically).
/// Vertex (i, j) (u index i, v index j) has index i * samplesV + j, position S(u_i, v_j) and the
/// unit normal Su x Sv. Each grid cell (i, j) is split along the diagonal (i, j)-(i+1, j+1) into
/// the triangles [(i,j), (i+1,j), (i+1,j+1)] and [(i,j), (i+1,j+1), (i,j+1)], wound so that the
/// right-hand normal points along Su x Sv: the orientation is consistent over the whole mesh.
/// Where Su x Sv vanishes (|Su x Sv| <= 1e-10 (control box diagonal)^2 / (domain lengths), a
/// degenerate parameterisation such as a pole where a control row collapses to a point) the vertex
/// normal is its limit: Su x Sv at parameters moved into the domain by 1e-7 (then 1e-5, 1e-3) of
/// its length; if that stays degenerate, the area-weighted mean of the adjacent triangles'
/// normals. Pole vertices are not merged, so such grids keep zero-area triangles there.
/// Evaluation runs in parallel (TBB); the result does not depend on the thread count.
/// Throws InputError for too few samples, more than 2^32 - 1 vertices, or a surface so degenerate
/// that some vertex has no normal at all (e.g. all control points equal).
TriangleMesh tessellate(const BSplineSurface& surface, int samplesU, int samplesV);

}  // namespace d2vdb
