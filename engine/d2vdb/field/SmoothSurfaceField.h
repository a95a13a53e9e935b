// The approximant field of a smooth surface built from a mesh: every band voxel's footpoint is
// its exact projection onto the surface, its curvatures the surface's own.
#pragma once

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/manifold/PseudoManifold.h"

#include <string>

namespace d2vdb {

/// One line stored with fields built by smoothSurfaceField() (shown by `d2vdb info`).
inline constexpr const char* kSmoothSurfaceEstimator =
    "exact projection onto the smooth surface (parametric pseudo-manifold)";

/// Builds the approximant field of a smooth surface built from a mesh (PseudoManifold.h): the band
/// holds every voxel (cubic, `voxelSize`, voxel (i, j, k) centred at (i, j, k) voxelSize) whose
/// distance to the surface is below halfWidth voxels, found from seeds on the surface at most 1.2
/// voxels apart (a barycentric lattice per face, refined until neighbouring seeds are that close);
/// each voxel's approximant is SmoothSurface::approximantOf() the voxel centre's projection onto
/// the surface: the exact footpoint, signed distance, the surface's own normal, k1 >= k2 and e1
/// there, not second differences of a level set. The candidates are the voxels within halfWidth
/// + 0.9 voxel of a seed (FieldBand::nearSeeds with that reach); those whose nearest seed is
/// further than that (a bound on their distance to the surface) are not projected. The
/// projection (PseudoManifold::project(), Newton's method) starts from the projection of a
/// neighbour visited before the voxel in the same 8^3 leaf node: of the face neighbours (-z, -y,
/// -x) whose projection ended on a cubic Taylor model of the surface, the one whose model is
/// expanded nearest to the voxel's centre, else an edge or corner neighbour with such a model,
/// else a face neighbour's footpoint with its derivatives (and, along a line of such starts, its
/// second-order correction); from the nearest seed when no neighbour was projected, and again
/// from the nearest seed when the result is further than that seed or that seed lies away from
/// the result's footpoint, on another sheet (near the medial axis). Every start depends only on
/// the leaf, so the field does not depend on the order of the voxels or the thread count. From a
/// neighbour's model the voxel starts at that model's closest point
/// (SmoothProjectionOptions::startFromModel); the iteration ends on the cubic model at its last
/// iterate once the Newton step there is below 1e-3 of the chart radius
/// (SmoothProjectionOptions::cubicFinish), or with the last step's geometry extrapolated
/// (extrapolateLastStep): footpoints within about 1e-9 of the chart radius of the exact ones,
/// curvatures within about 1e-5 of their value, far below their half-precision storage. Curvatures
/// beyond 1 / voxel are clamped to it and flagged kFlagCurvatureClamped, as the level-set estimator
/// does; kFlagCutLocus and kFlagDegradedEstimate as SmoothSurface sets them. The working domain
/// pads the bounding box of the seeds (options); `label` says what the field is of (describe(),
/// e.g. the input file's name). Parallel (TBB), deterministic. Throws InputError for a non-positive
/// or non-finite voxel size, halfWidth outside 1..64, more than 4 x options.maxActiveVoxels seeds
/// or a band over options.maxActiveVoxels (before the approximants are computed).
ApproximantField smoothSurfaceField(const PseudoManifold& surface, double voxelSize,
                                    double halfWidth, const std::string& label = {},
                                    const ApproximantFieldOptions& options = {},
                                    const ProgressCallback& progress = {});

}  // namespace d2vdb
