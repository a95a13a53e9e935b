// Preparing a mesh for inside/outside decisions (welding, winding repair, hole caps) and the
// generalised winding number and closest-feature side queries on it.
#include "d2vdb/field/detail/InsideOutsideMesh.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
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

/// Each vertex replaced by the lowest-numbered vertex at exactly the same position.
std::vector<TriangleIndices> weld(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<TriangleIndices>& triangles) {
  std::vector<std::uint32_t> byPosition(points.size());
  std::iota(byPosition.begin(), byPosition.end(), std::uint32_t{0});
  tbb::parallel_sort(byPosition.begin(), byPosition.end(),
                     [&points](std::uint32_t a, std::uint32_t b) {
                       const Eigen::Vector3d& p = points[a];
                       const Eigen::Vector3d& q = points[b];
                       if (p.x() != q.x()) return p.x() < q.x();
                       if (p.y() != q.y()) return p.y() < q.y();
                       if (p.z() != q.z()) return p.z() < q.z();
                       return a < b;
                     });
  std::vector<std::uint32_t> canonical(points.size());
  for (std::size_t i = 0; i < byPosition.size();) {
    std::size_t j = i + 1;
    while (j < byPosition.size() && points[byPosition[j]] == points[byPosition[i]]) ++j;
    for (std::size_t k = i; k < j; ++k) canonical[byPosition[k]] = byPosition[i];
    i = j;
  }
  std::vector<TriangleIndices> welded(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) welded[t][k] = canonical[triangles[t][k]];
  }
  return welded;
}

double triangleArea(const std::vector<Eigen::Vector3d>& p, const TriangleIndices& tri) {
  return 0.5 * (p[tri[1]] - p[tri[0]]).cross(p[tri[2]] - p[tri[0]]).norm();
}

/// The half-edges of `keys` (sortedHalfEdges() of some triangles) after reversing the triangles
/// marked in `flip`: reversing (c0, c1, c2) to (c0, c2, c1) turns half-edge k into half-edge
/// 2 - k running the other way. Equal edges stay together; within them the order by half-edge
/// is restored, so that the result equals sortedHalfEdges() of the reversed triangles.
void reverseHalfEdges(std::vector<HalfEdgeKey>& keys, const std::vector<std::uint8_t>& flip) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      HalfEdgeKey& key = keys[i];
      const std::uint32_t t = key.halfEdge / 3;
      if (!flip[t]) continue;
      key.halfEdge = 3 * t + (2 - key.halfEdge % 3);
      key.forward = !key.forward;
    }
  });
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].edge == keys[i].edge) ++j;
    if (j - i > 1) {
      std::sort(keys.begin() + i, keys.begin() + j,
                [](const HalfEdgeKey& x, const HalfEdgeKey& y) { return x.halfEdge < y.halfEdge; });
    }
    i = j;
  }
}

/// Whether the triangles, with those marked in `flip` reversed, are inside out: a negative signed
/// volume about the centre of their bounding box.
bool insideOut(const std::vector<Eigen::Vector3d>& p, const std::vector<TriangleIndices>& triangles,
               const std::vector<std::uint8_t>& flip) {
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  for (const TriangleIndices& tri : triangles) {
    for (const std::uint32_t corner : tri) {
      low = low.cwiseMin(p[corner]);
      high = high.cwiseMax(p[corner]);
    }
  }
  const Eigen::Vector3d center = 0.5 * (low + high);
  double volume = 0.0;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const TriangleIndices& tri = triangles[t];
    const double det = (p[tri[0]] - center).dot((p[tri[1]] - center).cross(p[tri[2]] - center));
    volume += flip[t] ? -det : det;
  }
  return volume < 0.0;
}

/// Reverses triangles so that edges shared by two triangles are traversed once each way (see
/// the header). `keys` are sortedHalfEdges(triangles) before and after. Returns the number of
/// reversed triangles.
std::size_t repairOrientation(const std::vector<Eigen::Vector3d>& p,
                              std::vector<TriangleIndices>& triangles,
                              std::vector<HalfEdgeKey>& keys) {
  const auto count = static_cast<std::uint32_t>(triangles.size());
  std::vector<std::uint32_t> pairedWith(3 * std::size_t{count}, kNoMate);
  std::vector<bool> sameDirection(3 * std::size_t{count}, false);
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
  std::vector<std::uint8_t> flip(count, 0);
  std::vector<std::uint32_t> component(count, kNoMate);
  std::vector<double> flippedArea, keptArea;
  std::deque<std::uint32_t> queue;
  for (std::uint32_t root = 0; root < count; ++root) {
    if (component[root] != kNoMate) continue;
    const auto id = static_cast<std::uint32_t>(flippedArea.size());
    flippedArea.push_back(0.0);
    keptArea.push_back(0.0);
    component[root] = id;
    queue.push_back(root);
    while (!queue.empty()) {
      const std::uint32_t t = queue.front();
      queue.pop_front();
      (flip[t] ? flippedArea : keptArea)[id] += triangleArea(p, triangles[t]);
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t other = pairedWith[3 * t + k];
        if (other == kNoMate || component[other / 3] != kNoMate) continue;
        component[other / 3] = id;
        flip[other / 3] = flip[t] ^ (sameDirection[3 * t + k] ? 1 : 0);
        queue.push_back(other / 3);
      }
    }
  }
  for (std::uint32_t t = 0; t < count; ++t) {
    if (flippedArea[component[t]] > keptArea[component[t]]) flip[t] ^= 1;
  }
  // An inside-out mesh is turned right side out.
  if (insideOut(p, triangles, flip)) {
    for (std::uint8_t& f : flip) f ^= 1;
  }
  std::size_t reversed = 0;
  for (std::uint32_t t = 0; t < count; ++t) {
    if (!flip[t]) continue;
    std::swap(triangles[t][1], triangles[t][2]);
    ++reversed;
  }
  if (reversed > 0) reverseHalfEdges(keys, flip);
  return reversed;
}

/// The directed edges traversed more often one way than the other (with multiplicity), as
/// closed loops of vertices. `keys` are the sorted half-edges of `triangles`.
std::vector<std::vector<std::uint32_t>> boundaryLoops(const std::vector<HalfEdgeKey>& keys,
                                                      std::size_t vertexCount,
                                                      std::size_t& boundaryEdges) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // (from, to), sorted by from
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i;
    long balance = 0;
    for (; j < keys.size() && keys[j].edge == keys[i].edge; ++j)
      balance += keys[j].forward ? 1 : -1;
    const auto small = static_cast<std::uint32_t>(keys[i].edge >> 32);
    const auto large = static_cast<std::uint32_t>(keys[i].edge & 0xffffffffu);
    for (long m = 0; m < std::abs(balance); ++m) {
      edges.emplace_back(balance > 0 ? small : large, balance > 0 ? large : small);
    }
    i = j;
  }
  boundaryEdges = edges.size();
  std::vector<std::vector<std::uint32_t>> loops;
  if (edges.empty()) return loops;
  std::sort(edges.begin(), edges.end());
  std::vector<std::uint32_t> start(vertexCount + 1, 0);
  for (const auto& edge : edges) ++start[edge.first + 1];
  for (std::size_t v = 0; v < vertexCount; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);  // first unused per vertex
  // Every vertex has as many boundary edges in as out, so a walk from an unused edge along
  // unused edges returns to its start.
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const std::uint32_t origin = edges[e].first;
    if (next[origin] >= start[origin + 1] || next[origin] > e) continue;  // edge e used
    std::vector<std::uint32_t> loop;
    std::uint32_t at = origin;
    do {
      if (next[at] >= start[at + 1]) break;  // unreachable for a balanced boundary
      const std::uint32_t to = edges[next[at]++].second;
      loop.push_back(at);
      at = to;
    } while (at != origin);
    loops.push_back(std::move(loop));
  }
  return loops;
}

/// Closes the holes of M: a cone from each boundary loop's mean vertex; triangle (apex, b, a) for
/// the boundary edge a -> b, so that the cap traverses the loop the other way. `keys` are M's
/// sorted half-edges before, those of M + S after. `meshIsEmpty`: M has no triangles.
void closeHoles(InsideOutsideMesh& mesh, std::vector<HalfEdgeKey>& keys, bool meshIsEmpty) {
  const std::vector<std::vector<std::uint32_t>> loops =
      boundaryLoops(keys, mesh.points.size(), mesh.boundaryEdges);
  mesh.watertight = !meshIsEmpty && loops.empty();
  mesh.capLoops = loops.size();
  for (const std::vector<std::uint32_t>& loop : loops) {
    Eigen::Vector3d apex = Eigen::Vector3d::Zero();
    for (const std::uint32_t v : loop) apex += mesh.points[v];
    apex /= static_cast<double>(loop.size());
    const auto apexIndex = static_cast<std::uint32_t>(mesh.points.size());
    mesh.points.push_back(apex);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const std::uint32_t a = loop[i];
      const std::uint32_t b = loop[(i + 1) % loop.size()];
      mesh.caps.push_back({apexIndex, b, a});
    }
  }
  mesh.triangles.insert(mesh.triangles.end(), mesh.caps.begin(), mesh.caps.end());
  if (!mesh.caps.empty()) keys = sortedHalfEdges(mesh.triangles);
}

/// Marks the triangles of M + S with a repeated corner or |cross| <= 1e-10 * longest edge^2.
void markDegenerate(InsideOutsideMesh& mesh) {
  const std::vector<Eigen::Vector3d>& p = mesh.points;
  const auto triangleCount = static_cast<std::uint32_t>(mesh.triangles.size());
  mesh.degenerate.assign(triangleCount, false);
  for (std::uint32_t t = 0; t < triangleCount; ++t) {
    const TriangleIndices& tri = mesh.triangles[t];
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
}

/// Mates: edges of M + S shared by exactly two triangles traversed once each way. `keys` are the
/// sorted half-edges of M + S.
void pairMates(InsideOutsideMesh& mesh, const std::vector<HalfEdgeKey>& keys) {
  mesh.mate.assign(3 * mesh.triangles.size(), kNoMate);
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].edge == keys[i].edge) ++j;
    if (j - i == 2 && keys[i].forward != keys[i + 1].forward) {
      mesh.mate[keys[i].halfEdge] = keys[i + 1].halfEdge;
      mesh.mate[keys[i + 1].halfEdge] = keys[i].halfEdge;
    }
    i = j;
  }
}

/// Components across mates, numbered in the order of their first triangles.
void labelComponents(InsideOutsideMesh& mesh) {
  const auto triangleCount = static_cast<std::uint32_t>(mesh.triangles.size());
  mesh.component.assign(triangleCount, kNoMate);
  std::deque<std::uint32_t> queue;
  for (std::uint32_t root = 0; root < triangleCount; ++root) {
    if (mesh.component[root] != kNoMate) continue;
    const std::uint32_t id = mesh.componentCount++;
    mesh.component[root] = id;
    queue.push_back(root);
    while (!queue.empty()) {
      const std::uint32_t t = queue.front();
      queue.pop_front();
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t other = mesh.mate[3 * t + k];
        if (other == kNoMate || mesh.component[other / 3] != kNoMate) continue;
        mesh.component[other / 3] = id;
        queue.push_back(other / 3);
      }
    }
  }
}

/// Unit face normals; zero for a degenerate triangle.
void computeFaceNormals(InsideOutsideMesh& mesh) {
  const std::vector<Eigen::Vector3d>& p = mesh.points;
  const auto triangleCount = static_cast<std::uint32_t>(mesh.triangles.size());
  mesh.faceNormal.assign(triangleCount, Eigen::Vector3d::Zero());
  for (std::uint32_t t = 0; t < triangleCount; ++t) {
    if (mesh.degenerate[t]) continue;
    const TriangleIndices& tri = mesh.triangles[t];
    mesh.faceNormal[t] = (p[tri[1]] - p[tri[0]]).cross(p[tri[2]] - p[tri[0]]).normalized();
  }
}

/// The corners of M + S grouped by vertex: those of vertex v are corners[start[v]..start[v + 1]),
/// each as the half-edge 3 t + k leaving v in its triangle, in triangle order.
struct VertexCorners {
  std::vector<std::uint32_t> start;
  std::vector<std::uint32_t> corners;
};

VertexCorners cornersByVertex(const InsideOutsideMesh& mesh) {
  const std::size_t vertexCount = mesh.points.size();
  const auto triangleCount = static_cast<std::uint32_t>(mesh.triangles.size());
  VertexCorners result;
  std::vector<std::uint32_t>& start = result.start;
  start.assign(vertexCount + 1, 0);
  for (const TriangleIndices& tri : mesh.triangles) {
    for (const std::uint32_t corner : tri) ++start[corner + 1];
  }
  for (std::size_t v = 0; v < vertexCount; ++v) start[v + 1] += start[v];
  result.corners.resize(start.back());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::uint32_t t = 0; t < triangleCount; ++t) {
    for (std::uint32_t k = 0; k < 3; ++k) {
      result.corners[fill[mesh.triangles[t][k]]++] = 3 * t + k;
    }
  }
  return result;
}

/// Sets `normal` to the angle-weighted pseudonormal of the vertex whose `degree` corners start
/// at `corners`, unless its triangles do not form one closed fan or touch a degenerate triangle
/// (then `normal` is left alone).
void setClosedFanNormal(const InsideOutsideMesh& mesh, const std::uint32_t* corners,
                        std::uint32_t degree, Eigen::Vector3d& normal) {
  const std::vector<Eigen::Vector3d>& p = mesh.points;
  bool usable = true;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::uint32_t i = 0; i < degree; ++i) {
    const std::uint32_t t = corners[i] / 3;
    const std::uint32_t k = corners[i] % 3;
    if (mesh.degenerate[t]) {
      usable = false;
      break;
    }
    const TriangleIndices& tri = mesh.triangles[t];
    const Eigen::Vector3d e1 = (p[tri[(k + 1) % 3]] - p[tri[k]]).normalized();
    const Eigen::Vector3d e2 = (p[tri[(k + 2) % 3]] - p[tri[k]]).normalized();
    sum += std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * mesh.faceNormal[t];
  }
  // One closed fan: walking across the mates from the first corner returns to it after visiting
  // every incident triangle.
  const std::uint32_t first = corners[0];  // leaves v in its triangle
  std::uint32_t halfEdge = first;
  std::uint32_t steps = 0;
  while (usable && steps <= degree) {
    const std::uint32_t other = mesh.mate[halfEdge];
    if (other == kNoMate) {
      usable = false;
      break;
    }
    // `other` arrives at v; the next half-edge of its triangle leaves v.
    halfEdge = 3 * (other / 3) + (other % 3 + 1) % 3;
    ++steps;
    if (halfEdge == first) break;
  }
  if (usable && steps == degree && halfEdge == first) normal = sum;
}

/// Vertex pseudonormals: incident corners by vertex, then the fan walk through the mates.
void computeVertexNormals(InsideOutsideMesh& mesh) {
  const std::size_t vertexCount = mesh.points.size();
  const VertexCorners incident = cornersByVertex(mesh);
  mesh.vertexNormal.assign(vertexCount, Eigen::Vector3d::Zero());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertexCount), [&](const auto& range) {
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const std::uint32_t degree = incident.start[v + 1] - incident.start[v];
      if (degree == 0) continue;
      setClosedFanNormal(mesh, incident.corners.data() + incident.start[v], degree,
                         mesh.vertexNormal[v]);
    }
  });
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
  mesh.meshTriangleCount = static_cast<std::uint32_t>(input.size());
  mesh.triangles = weld(mesh.points, input);
  // M's half-edges sorted by edge, kept up to date through the repair and extended by the caps'.
  std::vector<HalfEdgeKey> keys = sortedHalfEdges(mesh.triangles);
  mesh.reorientedTriangles = repairOrientation(mesh.points, mesh.triangles, keys);
  closeHoles(mesh, keys, input.empty());
  markDegenerate(mesh);
  pairMates(mesh, keys);
  labelComponents(mesh);
  computeFaceNormals(mesh);
  computeVertexNormals(mesh);
  return mesh;
}

}  // namespace d2vdb::detail
