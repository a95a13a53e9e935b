#include "d2vdb/support/SupportSamples.h"

#include <cmath>

#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/VertexNormals.h"

namespace d2vdb {

SampleCheck checkOrientedSamples(OrientedSamples& samples, const std::string& sourceName) {
  if (samples.points.size() != samples.normals.size()) {
    throw InputError(sourceName + ": " + std::to_string(samples.points.size()) + " points but " +
                     std::to_string(samples.normals.size()) + " normals");
  }
  if (samples.points.empty()) throw InputError(sourceName + ": no samples");
  SampleCheck check;
  for (std::size_t i = 0; i < samples.points.size(); ++i) {
    if (!samples.points[i].allFinite()) {
      throw InputError(sourceName + ": sample " + std::to_string(i) + " has a non-finite point");
    }
    Eigen::Vector3d& n = samples.normals[i];
    if (!n.allFinite()) {
      throw InputError(sourceName + ": sample " + std::to_string(i) + " has a non-finite normal");
    }
    const double length = n.norm();
    if (!(length > 1e-150)) {
      throw InputError(sourceName + ": sample " + std::to_string(i) +
                       " has a zero normal (every sample needs a direction)");
    }
    const double deviation = std::abs(length - 1.0);
    if (deviation > 1e-3) ++check.renormalised;
    if (deviation > check.largestDeviation) check.largestDeviation = deviation;
    n /= length;
  }
  return check;
}

OrientedSamples samplesFromMesh(const TriangleMesh& mesh, const std::string& sourceName) {
  if (mesh.positions.empty()) throw InputError(sourceName + ": the mesh has no vertices");
  TriangleMesh withNormals;
  const TriangleMesh* source = &mesh;
  if (!mesh.hasNormals()) {
    if (mesh.triangles.empty()) {
      throw InputError(sourceName +
                       ": a point set needs a normal per point (PLY properties nx, ny, nz) to be "
                       "fitted by a support function");
    }
    withNormals = mesh;
    computeVertexNormals(withNormals);
    source = &withNormals;
  }
  std::vector<bool> used(mesh.positions.size(), mesh.triangles.empty());
  for (const auto& triangle : mesh.triangles) {
    for (const auto index : triangle) {
      if (index >= used.size()) {
        throw InputError(sourceName + ": a triangle refers to vertex " + std::to_string(index) +
                         " of " + std::to_string(used.size()));
      }
      used[index] = true;
    }
  }
  OrientedSamples samples;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    if (!used[v]) continue;
    samples.points.push_back(source->positions[v].cast<double>());
    samples.normals.push_back(source->normals[v].cast<double>());
  }
  return samples;
}

}  // namespace d2vdb
