// How far a pseudo-manifold lies from the source surface it was fitted to, and from the triangle
// mesh it came from.
#pragma once

#include <Eigen/Core>

#include <cstddef>

#include "d2vdb/manifold/HalfEdgeMesh.h"
#include "d2vdb/manifold/PseudoManifold.h"
#include "d2vdb/manifold/SourceSurface.h"
#include "d2vdb/mesh/MeshDistance.h"

namespace d2vdb {

/// The barycentric lattice of a face with `samplesPerEdge` intervals per edge:
/// points (i, j) with b1 = i / s, b2 = j / s, i + j <= s, in the order i outer, j inner.
std::vector<Eigen::Vector3d> faceLattice(int samplesPerEdge);

/// A point of a source surface near x: the end of a Gauss-Newton descent of |S(face, b) - x|^2
/// from `start`, steps taken in the faces' canonical triangles and continued across edges into the
/// neighbouring faces (unfolded about the shared edge). `distance` = |S - x| is an upper bound of
/// the distance from x to the surface and equals it at a local minimum.
struct SourceProjection {
  FacePoint point;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double distance = 0.0;
};
/// Throws InputError for a non-finite x or a face out of range.
SourceProjection projectOntoSource(const SourceSurface& source, const Eigen::Vector3d& x,
                                   const FacePoint& start);

/// Distances from a pseudo-manifold to its source at the lattice points of every face.
struct SourceDistanceStatistics {
  std::size_t samples = 0;
  double maxDistance = 0.0;    ///< world units
  double rmsDistance = 0.0;    ///< world units
  double maxParametric = 0.0;  ///< max |PPS(f, b) - S(f, b)| (same parameters), world units
  double rmsParametric = 0.0;
  double diagonal = 0.0;  ///< bounding-box diagonal of the mesh, for relative figures
};

/// For each lattice point (faceLattice(samplesPerEdge)) of every faceStep-th face (all faces by
/// default): the distance from the PPS point to the source, found by projectOntoSource from the
/// same face point (an upper bound of the exact distance, equal to it at the local minimum
/// found), and the parametric deviation. Parallel (TBB), deterministic. Throws InputError when
/// the surfaces have different meshes, samplesPerEdge < 1 or faceStep < 1.
SourceDistanceStatistics distanceToSource(const PseudoManifold& surface,
                                          const SourceSurface& source, int samplesPerEdge,
                                          int faceStep = 1);

/// Distances from a pseudo-manifold to a triangle mesh.
struct MeshDeviationStatistics {
  std::size_t samples = 0;
  double maxDistance = 0.0;  ///< world units
  double rmsDistance = 0.0;  ///< world units
};

/// For each lattice point (faceLattice(samplesPerEdge)) of every faceStep-th face: the exact
/// distance from the PPS point to the nearest triangle of `mesh` (usually the mesh the surface
/// was built from: a Loop limit surface, and so the smooth surface, does not pass through the
/// mesh's vertices). One-sided, from the surface to the mesh. Parallel (TBB), deterministic.
/// Throws InputError when samplesPerEdge < 1 or faceStep < 1.
MeshDeviationStatistics distanceToMesh(const PseudoManifold& surface, const MeshDistance& mesh,
                                       int samplesPerEdge, int faceStep = 1);

}  // namespace d2vdb
