#include "d2vdb/support/SupportSamples.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

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
    if (!(n.cwiseAbs().maxCoeff() > 1e-150)) {
      throw InputError(sourceName + ": sample " + std::to_string(i) +
                       " has a zero normal (every sample needs a direction)");
    }
    const double deviation = std::abs(length - 1.0);
    if (deviation > 1e-3) ++check.renormalized;
    if (deviation > check.largestDeviation) check.largestDeviation = deviation;
    n = std::isfinite(length) && length > 1e-100 ? Eigen::Vector3d(n / length)
                                                 : unitNormalOrThrow(n, sourceName);
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

MeshGaussImage meshGaussImage(const TriangleMesh& mesh, const std::string& sourceName) {
  if (mesh.triangles.empty()) {
    throw InputError(sourceName + ": the mesh has no triangles, so it has no Gauss image");
  }
  MeshGaussImage image;
  image.samples = samplesFromMesh(mesh, sourceName);
  // Compact indices, as samplesFromMesh() keeps the used vertices in order.
  std::vector<SphericalTriangulation::Index> compact(mesh.positions.size(), 0);
  std::vector<bool> used(mesh.positions.size(), false);
  for (const auto& triangle : mesh.triangles) {
    for (const auto index : triangle) used[index] = true;
  }
  SphericalTriangulation::Index next = 0;
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (used[v]) compact[v] = next++;
  }
  std::vector<Eigen::Vector3d> unit = image.samples.normals;
  for (std::size_t i = 0; i < unit.size(); ++i) {
    unit[i] =
        unitNormalOrThrow(unit[i], sourceName + ": the normal of vertex " + std::to_string(i));
  }
  image.gaussImage.normals = unit;
  std::map<std::pair<SphericalTriangulation::Index, SphericalTriangulation::Index>, int> edges;
  for (const auto& triangle : mesh.triangles) {
    const SphericalTriangulation::Triangle t = {compact[triangle[0]], compact[triangle[1]],
                                                compact[triangle[2]]};
    for (int k = 0; k < 3; ++k) {
      ++edges[std::minmax(t[static_cast<std::size_t>(k)],
                          t[static_cast<std::size_t>((k + 1) % 3)])];
    }
    const Eigen::Vector3d& a = unit[t[0]];
    const Eigen::Vector3d& b = unit[t[1]];
    const Eigen::Vector3d& c = unit[t[2]];
    const double det = a.dot(b.cross(c));
    const double spread =
        (b - a).cross(c - a).norm() + (b - a).squaredNorm() + (c - a).squaredNorm();
    if (std::abs(det) <= 1e-12 * std::max(spread, 1e-300) || spread == 0.0) {
      ++image.collapsedTriangles;
      image.gaussImage.triangles.push_back(t);
    } else if (det > 0.0) {
      ++image.preservingTriangles;
      image.gaussImage.triangles.push_back(t);
    } else {
      ++image.reversingTriangles;
      image.gaussImage.triangles.push_back({t[0], t[2], t[1]});
    }
  }
  image.closed =
      std::all_of(edges.begin(), edges.end(), [](const auto& edge) { return edge.second == 2; });
  return image;
}

}  // namespace d2vdb
