#include "d2vdb/io/SupportInput.h"

#include <openvdb/openvdb.h>

#include <cmath>
#include <utility>

#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb {
namespace {

// The samples of a mesh: a point set without triangles, else its Gauss image.
SupportInput meshSupportInput(const TriangleMesh& mesh, const std::filesystem::path& path) {
  SupportInput input;
  if (mesh.triangles.empty()) {
    input.kind = SupportInputKind::Points;
    input.samples = samplesFromMesh(mesh, quotedPath(path));
    return input;
  }
  MeshGaussImage image = meshGaussImage(mesh, quotedPath(path));
  input.samples = image.samples;
  input.kind = image.closed ? SupportInputKind::Mesh : SupportInputKind::MeshPatch;
  if (!image.closed) input.patch = image.gaussImage;
  if (!mesh.hasNormals()) {
    input.warnings.push_back(quotedPath(path) +
                             " has no vertex normals: using area-weighted normals of its "
                             "triangles, which limit the fit's accuracy to the facets' size");
  }
  input.gaussImage = std::move(image);
  return input;
}

}  // namespace

const char* supportInputKindName(SupportInputKind kind) {
  switch (kind) {
    case SupportInputKind::Mesh:
      return "mesh";
    case SupportInputKind::MeshPatch:
      return "mesh patch";
    case SupportInputKind::Points:
      return "points";
    case SupportInputKind::LevelSet:
      return "level set";
    case SupportInputKind::Field:
      return "field";
    case SupportInputKind::SupportFunction:
      return "support function";
  }
  return "unknown";
}

OrientedSamples samplesFromField(const ApproximantField& field, const std::string& source) {
  if (field.kind() != TargetKind::Surface) {
    throw InputError("'" + source + "' is a field of a " + targetKindName(field.kind()) +
                     ", not of a surface: a support function needs a closed surface");
  }
  const openvdb::FloatGrid::ConstPtr grid = field.distanceGrid();
  const double limit = 0.5 * field.voxelSize();
  ApproximantField::Accessor accessor(field);
  OrientedSamples samples;
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    if (std::abs(static_cast<double>(*it)) > limit) continue;
    const openvdb::Vec3d world = grid->indexToWorld(it.getCoord());
    const Approximant a = accessor.approximantAt(Eigen::Vector3d(world.x(), world.y(), world.z()));
    if ((a.flags & kFlagCutLocus) != 0) continue;
    samples.points.push_back(a.footpoint);
    samples.normals.push_back(a.normal);
  }
  if (samples.points.empty()) {
    throw InputError("'" + source + "' has no band voxels within half a voxel of its surface");
  }
  return samples;
}

SupportInput loadSupportInput(const std::filesystem::path& path, const ProgressCallback& progress) {
  LoadOptions load;
  load.purpose =
      "a support function's input (a mesh, a point set with normals as a .ply, a level set, a "
      "field, or a support-function .json)";
  load.progress = progress;
  // Without PointSet among the accepted kinds, a PLY without faces comes as a mesh of its
  // vertices, normals included.
  LoadedInput loaded =
      loadInput(path, {InputKind::Mesh, InputKind::Field, InputKind::SupportFunction}, load);
  if (loaded.kind() == InputKind::SupportFunction) {
    SupportInput input;
    input.kind = SupportInputKind::SupportFunction;
    input.document = std::move(loaded).take<SupportFunctionDocument>();
    return input;
  }
  if (loaded.kind() == InputKind::Field) {
    const FieldInput field = std::move(loaded).take<FieldInput>();
    SupportInput input;
    input.samples = samplesFromField(field.field, path.string());
    input.kind = field.stored ? SupportInputKind::Field : SupportInputKind::LevelSet;
    return input;
  }
  return meshSupportInput(std::move(loaded).take<MeshInput>().mesh, path);
}

CheckedSupport fitAndCheck(const SupportInput& input, const std::string& source,
                           const SupportFitSettings& settings) {
  const std::string sourceName = "'" + source + "'";
  CheckedSupport checked;
  if (input.document) {
    checked.document = *input.document;
  } else {
    DomainSupportFit fit =
        fitSupportOverDomain(input.samples, input.patch.has_value(), settings.degree,
                             settings.regularization, sourceName);
    const SupportFitReport& report = fit.report;
    checked.document.function = std::move(fit.function);
    checked.document.patch = input.patch;
    checked.document.fit =
        SupportFitRecord{std::filesystem::path(source).filename().string(), report.samples,
                         report.regularization, report.rmsResidual, report.maxResidual};
    checked.warnings = std::move(fit.warnings);
    checked.fit = report;
  }
  SupportCheck check =
      checkSupportFunction(checked.document.function, checked.document.patch, checked.fit,
                           input.gaussImage, sourceName, settings.allowSingular);
  checked.validity = std::move(check.validity);
  checked.warnings.insert(checked.warnings.end(), check.warnings.begin(), check.warnings.end());
  return checked;
}

CheckedSupport analyzeSupportDocument(SupportFunctionDocument document) {
  CheckedSupport checked;
  checked.document = std::move(document);
  checked.validity = analyzeSupportValidity(
      checked.document.function, validityDomain(checked.document.function, checked.document.patch));
  return checked;
}

std::vector<SupportFunctionDocument> supportPatchDocuments(const SupportPatchSet& set,
                                                           const std::string& source) {
  const std::string fileName = std::filesystem::path(source).filename().string();
  std::vector<SupportFunctionDocument> documents;
  for (const SupportPatch& p : set.patches) {
    SupportFunctionDocument document;
    document.function = p.function;
    document.patch = p.gaussImage.gaussImage;
    document.fit = SupportFitRecord{fileName, p.fit.samples, p.fit.regularization,
                                    p.fit.rmsResidual, p.fit.maxResidual};
    documents.push_back(std::move(document));
  }
  return documents;
}

PatchSurface loadPatchSurface(const std::filesystem::path& path, const ProgressCallback& progress) {
  LoadOptions load;
  load.purpose = "the input of --patches (a mesh with triangles or a level set)";
  load.progress = progress;
  LoadedInput loaded = loadInput(path, {InputKind::Mesh, InputKind::LevelSet}, load);
  PatchSurface surface;
  surface.kind = loaded.kind();
  if (loaded.kind() == InputKind::LevelSet) {
    const openvdb::FloatGrid::Ptr grid = std::move(loaded).take<LevelSetInput>().floatGrid();
    IsoSurfaceOptions iso;
    iso.computeNormals = true;
    surface.mesh = extractIsoSurface(*grid, iso, progress);
    if (surface.mesh.triangles.empty()) {
      throw InputError(quotedPath(path) + " has no zero crossing: its iso-surface is empty");
    }
    return surface;
  }
  surface.mesh = std::move(loaded).take<MeshInput>().mesh;
  if (surface.mesh.triangles.empty()) {
    throw InputError(quotedPath(path) +
                     " has no triangles: splitting into patches needs the surface's "
                     "connectivity (a mesh or a level set), not a point set");
  }
  if (!surface.mesh.hasNormals()) {
    surface.warnings.push_back(quotedPath(path) +
                               " has no vertex normals: using area-weighted normals of its "
                               "triangles, which limit the curvature signs and the fits' "
                               "accuracy to the facets' size");
  }
  return surface;
}

PatchedSupport fitPatches(const PatchSurface& surface, const SupportPatchOptions& options,
                          const std::string& source) {
  PatchedSupport patched;
  patched.kind = surface.kind;
  patched.warnings = surface.warnings;
  patched.set = fitSupportPatches(surface.mesh, options, "'" + source + "'");
  const SupportPatchSet& set = patched.set;
  if (set.patches.empty()) {
    throw InputError("'" + source + "': no region of one curvature sign could be fitted (" +
                     std::to_string(set.smallRegionTriangles) +
                     " triangles in regions too small, " + std::to_string(set.rejectedTriangles) +
                     " in regions whose fit failed, " + std::to_string(set.parabolicTriangles) +
                     " near-parabolic)");
  }
  const double uncovered =
      static_cast<double>(set.uncoveredTriangles()) / static_cast<double>(set.triangles);
  if (uncovered > 0.0) {
    patched.warnings.push_back(
        formatNumber(100.0 * uncovered, 3) + "% of the triangles are in no patch (" +
        std::to_string(set.parabolicTriangles) + " near parabolic curves, " +
        std::to_string(set.smallRegionTriangles) + " in regions too small to fit, " +
        std::to_string(set.rejectedTriangles) +
        " in regions whose fit failed): the patches' offsets leave gaps there");
  }
  return patched;
}

}  // namespace d2vdb
