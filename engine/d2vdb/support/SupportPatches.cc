// Splitting a non-convex mesh into regions of one curvature sign and fitting each over its Gauss
// image, cutting regions whose fit fails.
#include "d2vdb/support/SupportPatches.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/detail/DisjointSets.h"
#include "d2vdb/mesh/VertexNormals.h"

namespace d2vdb {
namespace {

// The mesh with one unit normal per vertex (its own, or area-weighted ones), indices checked.
TriangleMesh withNormals(const TriangleMesh& mesh, const std::string& sourceName) {
  if (mesh.triangles.empty()) {
    throw InputError(sourceName +
                     ": the mesh has no triangles, so it cannot be split into "
                     "patches of one curvature sign");
  }
  for (const auto& triangle : mesh.triangles) {
    for (const auto index : triangle) {
      if (index >= mesh.positions.size()) {
        throw InputError(sourceName + ": a triangle refers to vertex " + std::to_string(index) +
                         " of " + std::to_string(mesh.positions.size()));
      }
    }
  }
  TriangleMesh out = mesh;
  if (!out.hasNormals()) computeVertexNormals(out);
  return out;
}

// The sub-mesh of the given triangles, vertices renumbered in order of first use.
TriangleMesh subMesh(const TriangleMesh& mesh, const std::vector<std::size_t>& triangles) {
  TriangleMesh out;
  std::unordered_map<TriangleMesh::Index, TriangleMesh::Index> renumber;
  for (const std::size_t t : triangles) {
    TriangleMesh::Triangle triangle{};
    for (std::size_t k = 0; k < 3; ++k) {
      const TriangleMesh::Index v = mesh.triangles[t][k];
      const auto found = renumber.find(v);
      if (found != renumber.end()) {
        triangle[k] = found->second;
      } else {
        const auto index = static_cast<TriangleMesh::Index>(out.positions.size());
        renumber.emplace(v, index);
        out.positions.push_back(mesh.positions[v]);
        out.normals.push_back(mesh.normals[v]);
        triangle[k] = index;
      }
    }
    out.triangles.push_back(triangle);
  }
  return out;
}

double boundingDiagonal(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) return 0.0;
  Eigen::Vector3d lo = points.front();
  Eigen::Vector3d hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

struct PatchFitter {
  const TriangleMesh& mesh;
  const SupportPatchOptions& options;
  const std::string& sourceName;
  SupportPatchSet& result;

  // Fits the region; on failure cuts it in two and recurses.
  void fitRegion(RadiusSigns signs, std::vector<std::size_t> triangles, int depth) {
    if (triangles.size() < options.minTriangles) {
      result.rejectedTriangles += triangles.size();
      return;
    }
    SupportPatch patch;
    patch.signs = signs;
    patch.gaussImage = meshGaussImage(subMesh(mesh, triangles), sourceName);
    const std::size_t samples = patch.gaussImage.samples.points.size();
    int degree = options.degree;
    while (degree > 1 && static_cast<std::size_t>(3 * harmonicCount(degree)) > samples) --degree;
    bool accepted = false;
    if (static_cast<std::size_t>(harmonicCount(degree)) <= samples) {
      SupportFitOptions fitOptions;
      fitOptions.degree = degree;
      fitOptions.regularization = options.regularization;
      try {
        patch.function =
            fitSupportFunction(patch.gaussImage.samples, fitOptions, &patch.fit, sourceName);
        patch.validity = analyzeSupportValidity(patch.function, patch.gaussImage.gaussImage);
        accepted = patch.validity.regular() && patch.validity.signs == signs &&
                   patch.fit.maxResidual <= options.maxRelativeResidual *
                                                boundingDiagonal(patch.gaussImage.samples.points);
      } catch (const InputError&) {
        accepted = false;  // e.g. normals that do not determine the coefficients
      }
    }
    if (accepted) {
      patch.triangles = std::move(triangles);
      result.patches.push_back(std::move(patch));
      return;
    }
    if (depth >= options.maxSplitDepth) {
      result.rejectedTriangles += triangles.size();
      return;
    }
    // Cut at the median centroid along the longest side of the region's bounding box.
    std::vector<Eigen::Vector3d> centroids(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      const auto& t = mesh.triangles[triangles[i]];
      centroids[i] =
          (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]).cast<double>() / 3.0;
    }
    Eigen::Vector3d lo = centroids.front();
    Eigen::Vector3d hi = centroids.front();
    for (const auto& c : centroids) {
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
    Eigen::Index axis = 0;
    (hi - lo).maxCoeff(&axis);
    std::vector<std::size_t> order(triangles.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    const auto middle = order.begin() + static_cast<std::ptrdiff_t>(order.size() / 2);
    std::nth_element(order.begin(), middle, order.end(), [&](std::size_t a, std::size_t b) {
      const double ca = centroids[a][axis];
      const double cb = centroids[b][axis];
      return ca < cb || (ca == cb && triangles[a] < triangles[b]);
    });
    std::vector<std::size_t> first;
    std::vector<std::size_t> second;
    for (auto it = order.begin(); it != order.end(); ++it) {
      (it < middle ? first : second).push_back(triangles[*it]);
    }
    std::sort(first.begin(), first.end());
    std::sort(second.begin(), second.end());
    if (first.front() > second.front()) std::swap(first, second);
    fitRegion(signs, std::move(first), depth + 1);
    fitRegion(signs, std::move(second), depth + 1);
  }
};

}  // namespace

std::vector<RadiusSigns> classifyTriangles(const TriangleMesh& input, const std::string& sourceName,
                                           double parabolicRatio, int rings) {
  if (rings < 1 || rings > 20) {
    throw InputError("the curvature neighbourhood must be 1 to 20 rings of edges, got " +
                     std::to_string(rings));
  }
  const TriangleMesh mesh = withNormals(input, sourceName);
  const std::size_t vertexCount = mesh.positions.size();
  std::vector<Eigen::Vector3d> x(vertexCount);
  std::vector<Eigen::Vector3d> n(vertexCount);
  for (std::size_t v = 0; v < vertexCount; ++v) {
    x[v] = mesh.positions[v].cast<double>();
    n[v] = mesh.normals[v].cast<double>();
    const double length = n[v].norm();
    if (!std::isfinite(length) || length < 1e-150 || !x[v].allFinite()) {
      throw InputError(sourceName + ": vertex " + std::to_string(v) +
                       " has a zero or non-finite normal or position");
    }
    n[v] /= length;
  }
  // Neighbours along edges, sorted and unique.
  std::vector<std::vector<TriangleMesh::Index>> ring(vertexCount);
  for (const auto& t : mesh.triangles) {
    for (std::size_t k = 0; k < 3; ++k) {
      ring[t[k]].push_back(t[(k + 1) % 3]);
      ring[t[k]].push_back(t[(k + 2) % 3]);
    }
  }
  for (auto& r : ring) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  // Per vertex: the symmetric shape operator S on its tangent plane that best maps the offsets to
  // the neighbours within `rings` edges to their normals' changes, (n_j - n_i) = S (x_j - x_i)
  // projected (least squares in the three entries of S; the neighbourhood averages out the noise
  // of marching-cubes normals and the creases of faceted meshes). Its eigenvalues are the principal
  // curvatures, positive where the surface bends away from its normal.
  std::vector<RadiusSigns> vertexClass(vertexCount, RadiusSigns::Parabolic);
  std::vector<TriangleMesh::Index>
      neighborhood;  // the neighbourhood: vertices within `rings` edges
  std::vector<std::size_t> seenAt(vertexCount, std::numeric_limits<std::size_t>::max());
  std::vector<TriangleMesh::Index> frontier;
  std::vector<TriangleMesh::Index> next;
  for (std::size_t v = 0; v < vertexCount; ++v) {
    neighborhood.clear();
    frontier.assign(1, static_cast<TriangleMesh::Index>(v));
    seenAt[v] = v;
    for (int r = 0; r < rings; ++r) {
      next.clear();
      for (const auto a : frontier) {
        for (const auto b : ring[a]) {
          if (seenAt[b] == v) continue;
          seenAt[b] = v;
          next.push_back(b);
          neighborhood.push_back(b);
        }
      }
      frontier.swap(next);
    }
    const Eigen::Vector3d t1 = n[v].unitOrthogonal();
    const Eigen::Vector3d t2 = n[v].cross(t1);
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (const auto j : neighborhood) {
      const Eigen::Vector3d dx = x[j] - x[v];
      const Eigen::Vector3d dn = n[j] - n[v];
      const double a1 = dx.dot(t1), a2 = dx.dot(t2);
      const double b1 = dn.dot(t1), b2 = dn.dot(t2);
      // b1 = p a1 + q a2, b2 = q a1 + s a2 in the unknowns (p, q, s).
      const Eigen::Vector3d row1(a1, a2, 0.0);
      const Eigen::Vector3d row2(0.0, a1, a2);
      normal += row1 * row1.transpose() + row2 * row2.transpose();
      rhs += b1 * row1 + b2 * row2;
    }
    if (neighborhood.size() < 3) continue;
    const Eigen::LDLT<Eigen::Matrix3d> solver(normal);
    if (solver.info() != Eigen::Success || !(std::abs(normal.determinant()) > 0.0)) continue;
    const Eigen::Vector3d pqs = solver.solve(rhs);
    const double mean = 0.5 * (pqs[0] + pqs[2]);
    const double half = std::hypot(0.5 * (pqs[0] - pqs[2]), pqs[1]);
    const double k1 = mean - half;
    const double k2 = mean + half;
    const double larger = std::max(std::abs(k1), std::abs(k2));
    const double smaller = std::min(std::abs(k1), std::abs(k2));
    if (!std::isfinite(larger) || !(larger > 0.0) || smaller < parabolicRatio * larger) continue;
    vertexClass[v] = k1 > 0.0   ? RadiusSigns::Convex
                     : k2 < 0.0 ? RadiusSigns::Concave
                                : RadiusSigns::Saddle;
  }
  // A triangle takes its corners' class when they agree (else it straddles a parabolic curve).
  std::vector<RadiusSigns> classes(mesh.triangles.size(), RadiusSigns::Parabolic);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& triangle = mesh.triangles[t];
    const RadiusSigns c = vertexClass[triangle[0]];
    const bool degenerate =
        !((x[triangle[1]] - x[triangle[0]]).cross(x[triangle[2]] - x[triangle[0]]).norm() > 0.0);
    if (!degenerate && c == vertexClass[triangle[1]] && c == vertexClass[triangle[2]]) {
      classes[t] = c;
    }
  }
  // A vertex of a parabolic triangle lies on or next to a parabolic curve, where the Gauss map
  // folds: its normal is shared by nearby points of both sides, so every triangle touching it
  // counts as parabolic too (otherwise a region could hold samples with one normal and several
  // positions, which no support function fits).
  std::vector<bool> parabolicVertex(mesh.positions.size(), false);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (classes[t] != RadiusSigns::Parabolic) continue;
    for (const auto v : mesh.triangles[t]) parabolicVertex[v] = true;
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& triangle = mesh.triangles[t];
    if (parabolicVertex[triangle[0]] || parabolicVertex[triangle[1]] ||
        parabolicVertex[triangle[2]]) {
      classes[t] = RadiusSigns::Parabolic;
    }
  }
  return classes;
}

double SupportPatchSet::safeOffsetMin() const {
  double value = -std::numeric_limits<double>::infinity();
  for (const SupportPatch& p : patches) value = std::max(value, p.validity.safeOffsetMin);
  return value;
}

double SupportPatchSet::safeOffsetMax() const {
  double value = std::numeric_limits<double>::infinity();
  for (const SupportPatch& p : patches) value = std::min(value, p.validity.safeOffsetMax);
  return value;
}

SupportPatchSet fitSupportPatches(const TriangleMesh& input, const SupportPatchOptions& options,
                                  const std::string& sourceName) {
  if (options.degree < 1 || options.degree > kMaxSupportDegree) {
    throw InputError("patch degree " + std::to_string(options.degree) +
                     " is not supported (expected 1 to " + std::to_string(kMaxSupportDegree) + ")");
  }
  if (!(options.regularization >= 0.0) || !std::isfinite(options.regularization) ||
      !(options.maxRelativeResidual > 0.0) || options.maxSplitDepth < 0 ||
      options.maxSplitDepth > 30 || !(options.parabolicRatio >= 0.0) ||
      !(options.parabolicRatio < 1.0) || options.curvatureRings < 1 ||
      options.curvatureRings > 20) {
    throw InputError(
        "invalid patch options (regularisation >= 0, residual bound > 0, split "
        "depth 0..30)");
  }
  const TriangleMesh mesh = withNormals(input, sourceName);
  const std::vector<RadiusSigns> classes =
      classifyTriangles(mesh, sourceName, options.parabolicRatio, options.curvatureRings);
  SupportPatchSet result;
  result.triangles = mesh.triangles.size();
  for (const RadiusSigns c : classes) {
    switch (c) {
      case RadiusSigns::Convex:
        ++result.convexTriangles;
        break;
      case RadiusSigns::Saddle:
        ++result.saddleTriangles;
        break;
      case RadiusSigns::Concave:
        ++result.concaveTriangles;
        break;
      case RadiusSigns::Parabolic:
        ++result.parabolicTriangles;
        break;
    }
  }
  // Regions: triangles of one class that share an edge.
  detail::DisjointSets<std::size_t> components(mesh.triangles.size());
  std::unordered_map<std::uint64_t, std::size_t> firstOfEdge;
  firstOfEdge.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (classes[t] == RadiusSigns::Parabolic) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint64_t a = mesh.triangles[t][k];
      const std::uint64_t b = mesh.triangles[t][(k + 1) % 3];
      const std::uint64_t key = (std::min(a, b) << 32) | std::max(a, b);
      const auto [it, inserted] = firstOfEdge.emplace(key, t);
      if (!inserted && classes[it->second] == classes[t]) components.unite(it->second, t);
    }
  }
  std::vector<std::vector<std::size_t>> regions;
  std::unordered_map<std::size_t, std::size_t> regionOfRoot;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (classes[t] == RadiusSigns::Parabolic) continue;
    const std::size_t root = components.find(t);
    const auto [it, inserted] = regionOfRoot.emplace(root, regions.size());
    if (inserted) regions.emplace_back();
    regions[it->second].push_back(t);
  }
  PatchFitter fitter{mesh, options, sourceName, result};
  for (std::vector<std::size_t>& region : regions) {
    if (region.size() < options.minTriangles) {
      result.smallRegionTriangles += region.size();
      continue;
    }
    const RadiusSigns signs = classes[region.front()];
    fitter.fitRegion(signs, std::move(region), 0);
  }
  return result;
}

}  // namespace d2vdb
