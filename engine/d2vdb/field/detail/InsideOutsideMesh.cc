#include "d2vdb/field/detail/InsideOutsideMesh.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <deque>
#include <utility>

namespace d2vdb::detail {
namespace {

constexpr std::uint32_t kNoMate = InsideOutsideMesh::kNoMate;

/// One half-edge keyed by its undirected edge.
struct HalfEdgeKey {
  std::uint64_t edge;      ///< (smaller corner << 32) | larger corner
  std::uint32_t halfEdge;  ///< 3 t + k
  bool forward;            ///< runs from the smaller corner to the larger
};

bool repeatsCorner(const TriangleIndices& t) {
  return t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
}

/// Half-edges of the triangles without a repeated corner, sorted by undirected edge.
std::vector<HalfEdgeKey> sortedHalfEdges(const std::vector<TriangleIndices>& triangles) {
  std::vector<HalfEdgeKey> keys;
  keys.reserve(3 * triangles.size());
  for (std::uint32_t t = 0; t < triangles.size(); ++t) {
    if (repeatsCorner(triangles[t])) continue;
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint64_t a = triangles[t][k];
      const std::uint64_t b = triangles[t][(k + 1) % 3];
      keys.push_back({a < b ? (a << 32) | b : (b << 32) | a, 3 * t + k, a < b});
    }
  }
  tbb::parallel_sort(keys.begin(), keys.end(), [](const HalfEdgeKey& x, const HalfEdgeKey& y) {
    return x.edge < y.edge || (x.edge == y.edge && x.halfEdge < y.halfEdge);
  });
  return keys;
}

/// The half-edge of the flipped triangle (a, c, b) that runs along original side k reversed.
std::uint32_t flippedSide(std::uint32_t k) {
  return 2 - k;
}

}  // namespace

SurfaceSide InsideOutsideMesh::side(std::uint32_t triangle, const TriangleClosestPoint& closest,
                                    const Eigen::Vector3d& p) const {
  Eigen::Vector3d normal;
  switch (closest.feature) {
    case TriangleFeature::face:
      normal = faceNormal[triangle];
      break;
    case TriangleFeature::edge0:
    case TriangleFeature::edge1:
    case TriangleFeature::edge2: {
      const std::uint32_t k = static_cast<std::uint32_t>(closest.feature) -
                              static_cast<std::uint32_t>(TriangleFeature::edge0);
      const std::uint32_t other = mate[3 * triangle + k];
      if (other == kNoMate || degenerate[triangle] || degenerate[other / 3]) {
        return SurfaceSide::unknown;
      }
      normal = faceNormal[triangle] + faceNormal[other / 3];
      break;
    }
    default: {
      const std::uint32_t k = static_cast<std::uint32_t>(closest.feature) -
                              static_cast<std::uint32_t>(TriangleFeature::vertex0);
      normal = vertexNormal[triangles[triangle][k]];
      break;
    }
  }
  const Eigen::Vector3d offset = p - closest.point;
  const double along = offset.dot(normal);
  if (!(std::abs(along) > 1e-9 * offset.norm() * normal.norm())) return SurfaceSide::unknown;
  return along > 0.0 ? SurfaceSide::front : SurfaceSide::back;
}

InsideOutsideMesh prepareInsideOutsideMesh(std::vector<Eigen::Vector3d> points,
                                           const std::vector<TriangleIndices>& input) {
  InsideOutsideMesh mesh;
  mesh.points = std::move(points);
  const auto triangleCount = static_cast<std::uint32_t>(input.size());
  const std::vector<Eigen::Vector3d>& p = mesh.points;

  // Degenerate triangles.
  mesh.degenerate.assign(triangleCount, false);
  for (std::uint32_t t = 0; t < triangleCount; ++t) {
    const TriangleIndices& tri = input[t];
    bool flat = repeatsCorner(tri);
    if (!flat) {
      const Eigen::Vector3d ab = p[tri[1]] - p[tri[0]];
      const Eigen::Vector3d ac = p[tri[2]] - p[tri[0]];
      const Eigen::Vector3d bc = p[tri[2]] - p[tri[1]];
      const double longest2 = std::max({ab.squaredNorm(), ac.squaredNorm(), bc.squaredNorm()});
      flat = !(ab.cross(ac).norm() > 1e-10 * longest2);
    }
    if (flat) {
      mesh.degenerate[t] = true;
      ++mesh.degenerateTriangles;
    }
  }

  // Pair the half-edges of edges shared by exactly two triangles (before repair).
  const std::vector<HalfEdgeKey> keys = sortedHalfEdges(input);
  std::vector<std::uint32_t> pairedWith(3 * std::size_t{triangleCount}, kNoMate);
  std::vector<bool> sameDirection(3 * std::size_t{triangleCount}, false);
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].edge == keys[i].edge) ++j;
    if (j - i == 2) {
      pairedWith[keys[i].halfEdge] = keys[i + 1].halfEdge;
      pairedWith[keys[i + 1].halfEdge] = keys[i].halfEdge;
      const bool same = keys[i].forward == keys[i + 1].forward;
      sameDirection[keys[i].halfEdge] = same;
      sameDirection[keys[i + 1].halfEdge] = same;
    }
    i = j;
  }

  // Breadth-first orientation of each edge-connected component.
  std::vector<std::uint8_t> flip(triangleCount, 0);
  mesh.component.assign(triangleCount, kNoMate);
  std::deque<std::uint32_t> queue;
  std::vector<double> flippedArea, keptArea;
  std::vector<double> area(triangleCount);
  for (std::uint32_t t = 0; t < triangleCount; ++t) {
    const TriangleIndices& tri = input[t];
    area[t] = 0.5 * (p[tri[1]] - p[tri[0]]).cross(p[tri[2]] - p[tri[0]]).norm();
  }
  for (std::uint32_t root = 0; root < triangleCount; ++root) {
    if (mesh.component[root] != kNoMate) continue;
    const std::uint32_t id = mesh.componentCount++;
    flippedArea.push_back(0.0);
    keptArea.push_back(0.0);
    mesh.component[root] = id;
    queue.push_back(root);
    while (!queue.empty()) {
      const std::uint32_t t = queue.front();
      queue.pop_front();
      (flip[t] ? flippedArea : keptArea)[id] += area[t];
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t other = pairedWith[3 * t + k];
        if (other == kNoMate) continue;
        const std::uint32_t neighbour = other / 3;
        const std::uint8_t wanted = flip[t] ^ (sameDirection[3 * t + k] ? 1 : 0);
        if (mesh.component[neighbour] == kNoMate) {
          mesh.component[neighbour] = id;
          flip[neighbour] = wanted;
          queue.push_back(neighbour);
        }
      }
    }
  }
  for (std::uint32_t t = 0; t < triangleCount; ++t) {
    if (flippedArea[mesh.component[t]] > keptArea[mesh.component[t]]) flip[t] ^= 1;
  }
  // An inside-out mesh (negative signed volume about its box centre) is turned right side out.
  {
    Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d high = -low;
    for (const TriangleIndices& tri : input) {
      for (const std::uint32_t corner : tri) {
        low = low.cwiseMin(p[corner]);
        high = high.cwiseMax(p[corner]);
      }
    }
    const Eigen::Vector3d centre = 0.5 * (low + high);
    double volume = 0.0;
    for (std::uint32_t t = 0; t < triangleCount; ++t) {
      const TriangleIndices& tri = input[t];
      const double det = (p[tri[0]] - centre).dot((p[tri[1]] - centre).cross(p[tri[2]] - centre));
      volume += flip[t] ? -det : det;
    }
    if (volume < 0.0) {
      for (std::uint8_t& f : flip) f ^= 1;
    }
  }

  // The repaired triangles and their mates.
  mesh.triangles.resize(triangleCount);
  for (std::uint32_t t = 0; t < triangleCount; ++t) {
    const TriangleIndices& tri = input[t];
    mesh.triangles[t] = flip[t] ? TriangleIndices{tri[0], tri[2], tri[1]} : tri;
    if (flip[t]) ++mesh.reorientedTriangles;
  }
  const auto repairedSide = [&flip](std::uint32_t halfEdge) {
    const std::uint32_t t = halfEdge / 3;
    const std::uint32_t k = halfEdge % 3;
    return 3 * t + (flip[t] ? flippedSide(k) : k);
  };
  mesh.mate.assign(3 * std::size_t{triangleCount}, kNoMate);
  mesh.consistentlyOriented = true;
  for (std::uint32_t h = 0; h < pairedWith.size(); ++h) {
    const std::uint32_t other = pairedWith[h];
    if (other == kNoMate) continue;
    const bool same = sameDirection[h] != (flip[h / 3] != flip[other / 3]);
    if (same) {
      mesh.consistentlyOriented = false;  // a non-orientable component
      continue;
    }
    mesh.mate[repairedSide(h)] = repairedSide(other);
  }

  // Watertight: every undirected edge traversed equally often each way (after repair).
  mesh.watertight = triangleCount > 0;
  for (std::size_t i = 0; i < keys.size() && mesh.watertight;) {
    std::size_t j = i;
    long balance = 0;
    for (; j < keys.size() && keys[j].edge == keys[i].edge; ++j) {
      const bool forward = keys[j].forward != (flip[keys[j].halfEdge / 3] != 0);
      balance += forward ? 1 : -1;
    }
    if (balance != 0) mesh.watertight = false;
    i = j;
  }

  // Face normals.
  mesh.faceNormal.assign(triangleCount, Eigen::Vector3d::Zero());
  for (std::uint32_t t = 0; t < triangleCount; ++t) {
    if (mesh.degenerate[t]) continue;
    const TriangleIndices& tri = mesh.triangles[t];
    mesh.faceNormal[t] = (p[tri[1]] - p[tri[0]]).cross(p[tri[2]] - p[tri[0]]).normalized();
  }

  // Vertex pseudonormals: incident corners by vertex, then the fan walk through the mates.
  const std::size_t vertexCount = p.size();
  std::vector<std::uint32_t> start(vertexCount + 1, 0);
  for (const TriangleIndices& tri : mesh.triangles) {
    for (const std::uint32_t corner : tri) ++start[corner + 1];
  }
  for (std::size_t v = 0; v < vertexCount; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> corners(start.back());  // 3 t + k with corner k at the vertex
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t t = 0; t < triangleCount; ++t) {
      for (std::uint32_t k = 0; k < 3; ++k) corners[fill[mesh.triangles[t][k]]++] = 3 * t + k;
    }
  }
  mesh.vertexNormal.assign(vertexCount, Eigen::Vector3d::Zero());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertexCount), [&](const auto& range) {
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const std::uint32_t degree = start[v + 1] - start[v];
      if (degree == 0) continue;
      bool usable = true;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (std::uint32_t i = start[v]; i < start[v + 1] && usable; ++i) {
        const std::uint32_t t = corners[i] / 3;
        const std::uint32_t k = corners[i] % 3;
        if (mesh.degenerate[t]) {
          usable = false;
          break;
        }
        const TriangleIndices& tri = mesh.triangles[t];
        const Eigen::Vector3d e1 = (p[tri[(k + 1) % 3]] - p[tri[k]]).normalized();
        const Eigen::Vector3d e2 = (p[tri[(k + 2) % 3]] - p[tri[k]]).normalized();
        const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
        sum += angle * mesh.faceNormal[t];
      }
      // One closed fan: walking across the mates from the first corner returns to it after
      // visiting every incident triangle.
      std::uint32_t halfEdge = corners[start[v]];  // leaves v in its triangle
      std::uint32_t steps = 0;
      while (usable) {
        const std::uint32_t other = mesh.mate[halfEdge];
        if (other == kNoMate) {
          usable = false;
          break;
        }
        // `other` arrives at v; the next half-edge of its triangle leaves v.
        halfEdge = 3 * (other / 3) + (other % 3 + 1) % 3;
        ++steps;
        if (halfEdge == corners[start[v]] || steps > degree) break;
      }
      if (usable && steps == degree && halfEdge == corners[start[v]]) mesh.vertexNormal[v] = sum;
    }
  });
  return mesh;
}

}  // namespace d2vdb::detail
