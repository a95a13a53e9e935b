// Support functions of non-convex closed surfaces, patch by patch. A surface with parabolic curves
// (where the Gaussian curvature changes sign) has no global support function: its Gauss map is not
// injective. Each region of one curvature sign whose Gauss map is injective has one over its Gauss
// image (Sir, Gravesen, Juettler, "Curves and surfaces represented by polynomial support
// functions", Theoretical Computer Science 392, 2008, section 5: hyperbolic patches).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"
#include "d2vdb/support/SupportFit.h"
#include "d2vdb/support/SupportSamples.h"
#include "d2vdb/support/SupportValidity.h"

namespace d2vdb {

/// Parameters of fitSupportPatches().
struct SupportPatchOptions {
  /// Spherical-harmonic degree of each patch's fit; a patch with too few samples for it is fitted
  /// at the highest degree its samples determine (at least 3 samples per unknown).
  int degree = 16;
  /// Regularisation weight of each patch's fit (SupportFitOptions::regularization).
  double regularization = kPatchSupportRegularization;
  /// Regions of one curvature sign with fewer triangles than this are left out (reported as
  /// uncovered): too small to fit, typically slivers along the parabolic curves.
  std::size_t minTriangles = 60;
  /// A patch whose fit is singular over its Gauss image or misses its samples by more than
  /// `maxRelativeResidual` times its size (a fold or wrap of the Gauss map that the curvature
  /// signs do not show) is cut in two across its longest extent and refitted, up to this many
  /// times in a row.
  int maxSplitDepth = 4;
  /// Triangles whose smaller principal curvature (in magnitude) is below parabolicRatio times the
  /// larger are treated as parabolic and left out. Near a parabolic curve one radius grows without
  /// bound and the support function has a branch point just outside the region, which
  /// polynomials approximate slowly; leaving that band out keeps each region's fit accurate.
  double parabolicRatio = 0.1;
  /// The principal curvatures at a vertex are fitted over the vertices within this many edges
  /// (classifyTriangles): more rings average out noisy normals and facets.
  int curvatureRings = 2;
  /// Largest accepted max residual of a patch's fit, relative to the diagonal of its bounding box.
  double maxRelativeResidual = 5e-3;
};

/// One fitted patch: a connected region of the mesh of one curvature sign, its support function
/// over its Gauss image, and the checks of both.
struct SupportPatch {
  RadiusSigns signs = RadiusSigns::Convex;  ///< of the region's triangles (never Parabolic)
  std::vector<std::size_t> triangles;       ///< indices of the input mesh's triangles
  MeshGaussImage gaussImage;                ///< the region's samples and Gauss image
  SupportFunction function;                 ///< fitted over gaussImage.gaussImage
  SupportFitReport fit;
  SupportValidity validity;  ///< over the Gauss image
};

/// What fitSupportPatches() produced.
struct SupportPatchSet {
  std::vector<SupportPatch> patches;  ///< accepted patches (regular fit within the residual bound)
  std::size_t triangles = 0;          ///< of the input mesh
  std::size_t convexTriangles = 0;    ///< curvature classes of the input's triangles
  std::size_t saddleTriangles = 0;
  std::size_t concaveTriangles = 0;
  std::size_t parabolicTriangles = 0;    ///< Gauss image collapsed (flat, cylindrical, parabolic)
  std::size_t smallRegionTriangles = 0;  ///< in regions below minTriangles, left out
  std::size_t rejectedTriangles = 0;     ///< in regions whose fit failed at every split depth
  /// Triangles in no accepted patch.
  std::size_t uncoveredTriangles() const {
    std::size_t covered = 0;
    for (const SupportPatch& p : patches) covered += p.triangles.size();
    return triangles - covered;
  }
  /// The interval of offsets regular on every patch (intersection of their safe ranges).
  double safeOffsetMin() const;
  double safeOffsetMax() const;
};

/// The curvature class of each triangle of `mesh` from its vertices and vertex normals (given,
/// or area-weighted when the mesh has none). At each vertex, the symmetric shape operator S with
/// (n_j - n_i) = S (x_j - x_i) on the tangent plane is fitted by least squares over the vertices
/// within `rings` edges (1..20); its eigenvalues k1 <= k2 are the principal curvatures (positive
/// where the surface bends away from its normal): Convex (both > 0), Concave (both < 0), Saddle, or
/// Parabolic where min |k| < parabolicRatio max |k|. A triangle takes its corners' class when all
/// three agree, else (or when degenerate) it is Parabolic; every triangle sharing a vertex with a
/// parabolic one is Parabolic too (that vertex's normal belongs to both sides of the Gauss map's
/// fold). Normals must point out of the body. Throws InputError (naming `sourceName`) for a mesh
/// without triangles or with bad indices, normals or positions.
std::vector<RadiusSigns> classifyTriangles(const TriangleMesh& mesh, const std::string& sourceName,
                                           double parabolicRatio = 0.1, int rings = 2);

/// Splits `mesh` into connected regions (triangles sharing an edge) of one curvature class
/// (classifyTriangles), leaves out parabolic triangles and regions below options.minTriangles, and
/// fits a support function to each region over its Gauss image (fitSupportFunction on its vertices
/// with their normals, domain = the region's Gauss image). A region whose fit is singular on that
/// domain or whose residual exceeds options.maxRelativeResidual of its size is cut in two (by the
/// median of its triangles' centroids along the longest side of its bounding box) and each half
/// refitted, up to options.maxSplitDepth times; what still fails is counted as rejected, never
/// returned. Deterministic (patches in order of their first triangle). Throws InputError (naming
/// `sourceName`) for a mesh without triangles, bad indices or normals, or options out of range.
SupportPatchSet fitSupportPatches(const TriangleMesh& mesh, const SupportPatchOptions& options,
                                  const std::string& sourceName);

}  // namespace d2vdb
