// The smooth surface of a mesh in one call (SmoothSurfaceFromMesh.h).
#include "d2vdb/manifold/SmoothSurfaceFromMesh.h"

#include <chrono>
#include <cmath>
#include <utility>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/PnTriangles.h"

namespace d2vdb {
namespace {

/// Unit normals from the file when it has a usable one at every vertex, else nothing.
std::vector<Eigen::Vector3d> fileNormals(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> normals;
  if (!mesh.hasNormals()) return normals;
  for (const Eigen::Vector3f& n : mesh.normals) {
    const Eigen::Vector3d d = n.cast<double>();
    const double length = d.norm();
    if (!(length > 1e-12) || !std::isfinite(length)) return {};
    normals.push_back(d / length);
  }
  return normals;
}

std::shared_ptr<const HalfEdgeMesh> halfEdgeMeshOf(const TriangleMesh& mesh,
                                                   const std::string& label) {
  try {
    return std::make_shared<const HalfEdgeMesh>(mesh);
  } catch (const InputError& error) {
    if (label.empty()) throw;
    throw InputError(label + ": " + error.what());
  }
}

}  // namespace

const char* smoothSurfaceSourceName(SmoothSurfaceSource source) {
  return source == SmoothSurfaceSource::PnTriangles ? "pn" : "loop";
}

MeshSmoothSurface smoothSurfaceFromMesh(const TriangleMesh& mesh,
                                        const SmoothSurfaceFromMeshOptions& options,
                                        const ProgressCallback& progress) {
  std::shared_ptr<const HalfEdgeMesh> halfEdges = halfEdgeMeshOf(mesh, options.label);
  if (options.beforeBuilding) options.beforeBuilding(*halfEdges);

  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<SourceSurface> source;
  std::size_t subdividedFaces = 0;
  bool normalsFromFile = false;
  if (options.source == SmoothSurfaceSource::LoopLimit) {
    auto loop = std::make_unique<LoopLimitSurface>(halfEdges);
    subdividedFaces = loop->subdividedFaceCount();
    source = std::move(loop);
  } else {
    std::vector<Eigen::Vector3d> normals;
    if (options.fileNormals) normals = fileNormals(mesh);
    normalsFromFile = !normals.empty();
    source = normals.empty() ? std::make_unique<PnTriangles>(halfEdges)
                             : std::make_unique<PnTriangles>(halfEdges, std::move(normals));
  }
  PseudoManifold surface(*source, options.surface, progress);
  const double buildSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return MeshSmoothSurface{std::move(halfEdges), std::move(source), std::move(surface),
                           subdividedFaces,      normalsFromFile,   buildSeconds};
}

}  // namespace d2vdb
