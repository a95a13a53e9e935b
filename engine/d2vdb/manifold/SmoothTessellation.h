// A watertight triangle mesh sampled from a parametric pseudo-manifold.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

#include "d2vdb/core/ResourceBudget.h"
#include "d2vdb/manifold/PseudoManifold.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// A tessellation of a smooth surface with the surface's own normals and, when asked for, its
/// principal curvatures at every vertex.
struct SmoothTessellation {
  TriangleMesh mesh;                ///< float positions, unit normals from the derivatives
  std::vector<FacePoint> where;     ///< the face point each vertex was evaluated at
  std::vector<double> k1;           ///< per vertex (1 / world units), empty without curvature
  std::vector<double> k2;           ///< per vertex, k1 >= k2, empty without curvature
  std::vector<Eigen::Vector3d> e1;  ///< per vertex first principal direction, empty without
};

/// Number of triangles tessellateSmooth() makes: 4^levels per input face. Saturates at SIZE_MAX.
std::size_t smoothTessellationTriangles(const HalfEdgeMesh& mesh, int levels);

/// Number of vertices tessellateSmooth() makes: the used vertices, 2^levels - 1 per edge and
/// (2^levels - 1)(2^levels - 2) / 2 inside every face. A double, so that it cannot overflow.
double smoothTessellationVertices(const HalfEdgeMesh& mesh, int levels);

/// Peak memory (bytes) of tessellateSmooth() and of writing its result: per vertex its face point
/// (32 bytes), float position and normal (24), and with `curvature` k1, k2, e1 and the written
/// attributes (51); 24 bytes of triangles per vertex (two triangles each).
double estimateSmoothTessellationMemoryBytes(const HalfEdgeMesh& mesh, int levels, bool curvature);

/// Throws InputError, before anything is allocated, when the tessellation's memory
/// (estimateSmoothTessellationMemoryBytes()) or its file in `format` (estimateMeshFileBytes():
/// normals, and with `curvature` k1, k2 and colours) exceeds `budget`; the message names --lod,
/// the estimate and the largest level that fits.
void enforceSmoothTessellationBudget(const HalfEdgeMesh& mesh, int levels, bool curvature,
                                     MeshFormat format, const ResourceBudget& budget);

/// The checks tessellateSmooth() makes before allocating anything (so a caller can make them
/// before building the surface): throws InputError for levels outside 0..10 or more than
/// `maxTriangles` triangles.
void checkSmoothTessellation(const HalfEdgeMesh& mesh, int levels,
                             std::size_t maxTriangles = std::size_t{200} * 1000 * 1000);

/// Samples `surface` on the barycentric lattice with 2^levels intervals per edge of every face
/// (4^levels triangles per face). Each mesh vertex, each edge's interior lattice points and each
/// face's interior points are evaluated once and shared by the faces that meet there, so a closed
/// input gives a closed, manifold mesh with the input's orientation (watertight by construction:
/// no welding by distance). Vertex order: the used mesh vertices in index order, then the edges'
/// points (edges in the order of their smaller half-edge, points from that half-edge's start),
/// then the faces' interior points. `curvature` adds k1, k2 and e1 per vertex. Parallel (TBB),
/// deterministic.
///
/// Throws InputError for levels outside 0..10 or when the result would have more than
/// `maxTriangles` triangles (the message gives the count), before allocating it.
SmoothTessellation tessellateSmooth(const PseudoManifold& surface, int levels, bool curvature,
                                    std::size_t maxTriangles = std::size_t{200} * 1000 * 1000);

}  // namespace d2vdb
