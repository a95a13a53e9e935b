// Support functions of files: oriented samples of any input that has them (meshes, point sets with
// normals, level sets, fields) or a support-function file, fitted and checked in two calls, and
// the patches of one curvature sign of a non-convex surface (a mesh, or a level set's zero
// iso-surface):
//
//   const d2vdb::SupportInput input = d2vdb::loadSupportInput("ellipsoid.obj");
//   const d2vdb::CheckedSupport support = d2vdb::fitAndCheck(input, "ellipsoid.obj", {24});
//
//   const d2vdb::PatchSurface surface = d2vdb::loadPatchSurface("torus.vdb");
//   const d2vdb::PatchedSupport patches = d2vdb::fitPatches(surface, {}, "torus.vdb");
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/io/InputFile.h"
#include "d2vdb/io/SupportFunctionJson.h"
#include "d2vdb/mesh/TriangleMesh.h"
#include "d2vdb/support/SupportCheck.h"
#include "d2vdb/support/SupportFit.h"
#include "d2vdb/support/SupportPatches.h"
#include "d2vdb/support/SupportSamples.h"
#include "d2vdb/support/SupportValidity.h"

namespace d2vdb {

/// What a file given for a support function holds.
enum class SupportInputKind {
  Mesh,             ///< a closed mesh: fitted over the whole sphere
  MeshPatch,        ///< an open mesh: fitted over its own Gauss image
  Points,           ///< a point set with normals (a PLY without faces)
  LevelSet,         ///< a level set (.vdb): its band footpoints and normals
  Field,            ///< an approximant field stored by `d2vdb field`: its band footpoints
  SupportFunction,  ///< a support-function file: the function itself
};

/// The name reports give a kind: "mesh", "mesh patch", "points", "level set", "field" or
/// "support function" (the "input_kind" values of `d2vdb support` and `d2vdb offset`).
const char* supportInputKindName(SupportInputKind kind);

/// What a file gives a support function.
struct SupportInput {
  SupportInputKind kind = SupportInputKind::Mesh;
  OrientedSamples samples;                          ///< empty for a support-function file
  std::optional<SphericalTriangulation> patch;      ///< the Gauss image of an open mesh
  std::optional<MeshGaussImage> gaussImage;         ///< meshes: how the Gauss map orients triangles
  std::optional<SupportFunctionDocument> document;  ///< a support-function file
  std::vector<std::string> warnings;                ///< e.g. a mesh without vertex normals
};

/// Loads `path` through loadInput() (recognised by content): a mesh (its used vertices with their
/// normals, or area-weighted ones: MeshGaussImage), a PLY point set with nx ny nz, a .vdb level set
/// or field (samplesFromField()), or a support-function file. `progress` follows the reading or
/// building of a field. Throws InputError for any other kind or a malformed file, as loadInput()
/// and the samples' readers do.
SupportInput loadSupportInput(const std::filesystem::path& path,
                              const ProgressCallback& progress = {});

/// The band footpoints and normals of a surface's approximant field: one sample per active voxel
/// within half a voxel of the zero level (voxels flagged at the cut locus skipped), in the grid's
/// deterministic iteration order. Throws InputError (naming `source`) for a field of a curve or
/// points, or one without such voxels.
OrientedSamples samplesFromField(const ApproximantField& field, const std::string& source);

/// How fitAndCheck() fits and what it tolerates.
struct SupportFitSettings {
  int degree = 16;  ///< spherical-harmonic degree of the fit
  /// Smoothness weight of the fit; < 0: the default of the domain (kDefaultSupportRegularization
  /// over the sphere, kPatchSupportRegularization over an open mesh's Gauss image).
  double regularization = -1.0;
  /// Keep a function that is singular on its domain, or misses its samples, with a warning.
  bool allowSingular = false;
};

/// A fitted (or loaded) support function with its checks.
struct CheckedSupport {
  SupportFunctionDocument document;     ///< what `d2vdb support` writes
  std::optional<SupportFitReport> fit;  ///< when fitted here
  SupportValidity validity;             ///< over validityDomain() (SupportCheck.h)
  std::vector<std::string> warnings;
};

/// Fits the samples of `input` (fitSupportOverDomain(), over its patch when it has one) or takes
/// its support-function document, and checks the function over its domain
/// (checkSupportFunction()). `source` names the input in messages and, as a file name, in the
/// document's fit record. Throws InputError as those do: for samples that determine no function,
/// and unless settings.allowSingular for a function that is singular on its domain or misses its
/// samples by more than kMaxRelativeSupportResidual of their size.
CheckedSupport fitAndCheck(const SupportInput& input, const std::string& source,
                           const SupportFitSettings& settings = {});

/// The validity of a support-function document over its domain, as fitAndCheck() finds it but
/// without refusing a singular function (`d2vdb info`). Throws InputError for an invalid domain.
CheckedSupport analyzeSupportDocument(SupportFunctionDocument document);

/// The support-function documents of the patches of `set`, each over its own Gauss image with its
/// fit record (whose source is the file name of `source`, the input).
std::vector<SupportFunctionDocument> supportPatchDocuments(const SupportPatchSet& set,
                                                           const std::string& source);

/// A surface to split into patches, with where it came from.
struct PatchSurface {
  InputKind kind = InputKind::Mesh;  ///< Mesh, or LevelSet (its zero iso-surface)
  TriangleMesh mesh;                 ///< with triangles (and normals for a level set)
  std::vector<std::string> warnings;
};

/// Loads `path` as a mesh with triangles, or a level set (.vdb) whose zero iso-surface is extracted
/// (marching cubes, gradient normals; `progress` follows it). Throws InputError for point sets,
/// support-function files and anything else without the surface's connectivity, malformed files,
/// a mesh without triangles, or a level set without a zero crossing.
PatchSurface loadPatchSurface(const std::filesystem::path& path,
                              const ProgressCallback& progress = {});

/// The patches of a non-convex surface, with where they came from.
struct PatchedSupport {
  InputKind kind = InputKind::Mesh;  ///< the PatchSurface's
  SupportPatchSet set;
  std::vector<std::string> warnings;  ///< the surface's, then what the patches leave uncovered
};

/// Fits support-function patches of one curvature sign to `surface` (fitSupportPatches()).
/// `source` names the input in messages. Throws InputError as fitSupportPatches() does, and when
/// no region could be fitted (saying how many triangles were in regions too small, rejected or
/// near-parabolic); a warning says what share of the triangles is in no patch.
PatchedSupport fitPatches(const PatchSurface& surface, const SupportPatchOptions& options,
                          const std::string& source);

}  // namespace d2vdb
