// A smooth surface from a triangle mesh in one call: the half-edge mesh, the source surface (the
// Loop limit surface or PN triangles) and the parametric pseudo-manifold fitted to it.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "d2vdb/core/Progress.h"
#include "d2vdb/manifold/HalfEdgeMesh.h"
#include "d2vdb/manifold/PseudoManifold.h"
#include "d2vdb/manifold/SourceSurface.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// The surface a pseudo-manifold is fitted to.
enum class SmoothSurfaceSource {
  LoopLimit,    ///< the exact Loop limit surface (LoopLimitSurface.h)
  PnTriangles,  ///< curved PN triangles (PnTriangles.h)
};

/// The short name of a source, as SourceSurface::name() gives it: "loop" or "pn".
const char* smoothSurfaceSourceName(SmoothSurfaceSource source);

/// How smoothSurfaceFromMesh() builds the surface.
struct SmoothSurfaceFromMeshOptions {
  SmoothSurfaceSource source = SmoothSurfaceSource::LoopLimit;
  /// PN triangles: take the mesh's own vertex normals (normalised) when it has a finite one longer
  /// than 1e-12 at every vertex; otherwise, and when false, the area-weighted mean of the faces'
  /// normals. Not used by the Loop limit surface.
  bool fileNormals = false;
  /// The pseudo-manifold's construction parameters.
  PseudoManifoldOptions surface;
  /// Names the mesh in messages: prefixed to the half-edge mesh's InputError ("bunny.obj: ...");
  /// empty = no prefix.
  std::string label;
  /// Called with the half-edge mesh as soon as it is built, before the source surface and the
  /// pseudo-manifold (the expensive part): where a caller refuses a request early, e.g. with
  /// checkSmoothTessellation() or a voxel size check. May throw; empty = nothing.
  std::function<void(const HalfEdgeMesh&)> beforeBuilding;
};

/// What smoothSurfaceFromMesh() built. `surface` was fitted to `source`, whose mesh is `mesh`;
/// all three stay valid on their own (the source and the surface share the mesh).
struct MeshSmoothSurface {
  std::shared_ptr<const HalfEdgeMesh> mesh;
  std::unique_ptr<SourceSurface> source;  ///< a LoopLimitSurface or PnTriangles
  PseudoManifold surface;
  /// Loop limit surface: faces with two or three extraordinary corners, evaluated on one Loop
  /// subdivision step (LoopLimitSurface::subdividedFaceCount()); 0 for PN triangles.
  std::size_t subdividedFaces = 0;
  /// PN triangles: true when the mesh's own vertex normals were used (fileNormals).
  bool normalsFromFile = false;
  /// Wall-clock seconds spent on the source and the pseudo-manifold (after beforeBuilding).
  double buildSeconds = 0;
};

/// Builds the smooth (C-infinity) surface of a closed, 2-manifold, consistently oriented triangle
/// mesh: its half-edge mesh (HalfEdgeMesh.h), then the source surface of options.source, then the
/// parametric pseudo-manifold fitted to the source (PseudoManifold.h; Siqueira et al. 2009).
/// `progress` reports the pseudo-manifold's fitting stage. Throws InputError when the mesh is not
/// closed and manifold (HalfEdgeMesh's message, prefixed with options.label), for PN triangles
/// when a vertex's faces have no area, and for pseudo-manifold options out of range or over their
/// memory limit; whatever options.beforeBuilding throws propagates. Parallel (TBB), deterministic.
MeshSmoothSurface smoothSurfaceFromMesh(const TriangleMesh& mesh,
                                        const SmoothSurfaceFromMeshOptions& options = {},
                                        const ProgressCallback& progress = {});

}  // namespace d2vdb
