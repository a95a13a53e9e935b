// The estimator of surface approximants from a narrow-band level set (used by ApproximantField).
#pragma once

#include <openvdb/openvdb.h>

#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/detail/BandLayout.h"
#include "d2vdb/field/detail/RecordCodec.h"

namespace d2vdb::detail {

/// One line naming the method, stored as metadata and shown by `d2vdb info`.
inline constexpr const char* kSurfaceEstimator =
    "least-squares quadric fit of d over the 27-voxel stencil of every voxel within 1.75 voxels "
    "of the surface, gradient and Hessian interpolated trilinearly at the footpoint (found by "
    "tangent-plane projection), Hessian diagonalised in the tangent plane";

/// The record of every band voxel of a signed level set (the layout's grid: world units, d < 0
/// inside), in the layout's order, encoded with `codec` (a surface codec of the layout's frame).
///
/// Pass 1: for every active voxel within 1.75 voxels of the surface whose 26 neighbours are all
/// active, the least-squares quadric of d over the 3x3x3 stencil: on that symmetric stencil the
/// monomials {1, x, y, z, x^2 - 2/3, y^2 - 2/3, z^2 - 2/3, xy, xz, yz} are orthogonal, so the fit
/// is a fixed filter: g_x = sum x f / 18 (central differences averaged over the 9 rows),
/// H_xx = (sum_{x=+-1} f - 2 sum_{x=0} f) / 9 (second differences averaged over 9 rows),
/// H_xy = sum x y f / 12. Other voxels get a gradient from the central or one-sided differences
/// their active neighbours allow.
/// Pass 2: for every active voxel p, the footpoint s with p - s parallel to the normal at s and
/// d(s) = 0, by up to three rounds (fewer once the footpoint moves by less than 0.02 voxel) of:
/// interpolate d, grad d (trilinearly, from the pass-1 data of the 8 voxels around s), project onto
/// the zero level, re-aim along the normal through p. The distance stored is the one this footpoint
/// implies. The Hessian interpolated at the footpoint is the shape operator there (on the surface,
/// Hessian(d) = sum k_i e_i e_i^T); its restriction to the tangent plane is diagonalised in closed
/// form: k1 >= k2, e1. Flags: kFlagDegradedEstimate where the voxels with a full stencil carry less
/// than half of the trilinear weight at the footpoint (weights are renormalised over them in any
/// case); kFlagCutLocus where the gradient at p is below 0.7 in length, the projection does not
/// converge to within 0.5 voxel, or 1 + d k_i < 0.05 (then normal and footpoint come from the local
/// gradient and the curvatures are 0); kFlagCurvatureClamped where |k| > 1/voxel. Parallel over
/// leaves (TBB), slab by slab (pass 1 one slab ahead of pass 2, so that pass-1 data are held for
/// three slabs, not the whole band); every record depends only on the input, so the result is
/// identical for any thread count. `progress` receives "field: approximants" after every slab.
std::vector<BandRecord> estimateSurfaceRecords(const BandLayout& layout, const RecordCodec& codec,
                                               const ProgressCallback& progress);

}  // namespace d2vdb::detail
