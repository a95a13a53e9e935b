// validateMesh(): referenced vertices, degenerate triangles, the edge table and per-edge
// topology, vertex fans, components and the Euler characteristic.
#include "d2vdb/mesh/MeshValidation.h"

#include <Eigen/Geometry>

#include <tbb/parallel_sort.h>

#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "d2vdb/core/detail/DisjointSets.h"
#include "d2vdb/mesh/detail/MeshIndexCheck.h"

namespace d2vdb {
namespace {

using Index = TriangleMesh::Index;

using DisjointSets = detail::DisjointSets<std::size_t>;

/// Half-edge h = 3 * t + k runs from corner k to corner (k + 1) % 3 of triangle t.
struct HalfEdgeKey {
  std::uint64_t edge;    ///< (smaller vertex << 32) | larger vertex
  std::size_t halfEdge;  ///< 3 * triangle + side
};

/// What lies across a half-edge (mate table entries that are not half-edge numbers).
constexpr std::size_t kBoundary = std::numeric_limits<std::size_t>::max();
constexpr std::size_t kNonManifold = kBoundary - 1;
constexpr std::size_t kNotAnEdge = kBoundary - 2;  // a side of a triangle with a repeated index

std::string plural(std::size_t count, const char* singular, const char* pluralForm) {
  return std::to_string(count) + " " + (count == 1 ? singular : pluralForm);
}

/// The topology gathered from the sorted edge table, and the boundary walk over it.
class Topology {
 public:
  explicit Topology(const TriangleMesh& mesh) : mesh_(mesh), mate_(3 * mesh.triangles.size()) {}

  std::size_t from(std::size_t halfEdge) const { return corner(halfEdge, 0); }
  std::size_t to(std::size_t halfEdge) const { return corner(halfEdge, 1); }

  std::size_t& mate(std::size_t halfEdge) { return mate_[halfEdge]; }

  /// Counts the closed chains of boundary half-edges. From each boundary edge the walk continues
  /// with the boundary edge reached by turning around the end vertex through the triangles that
  /// share manifold edges, so that loops touching at a vertex stay separate; where that rotation
  /// is blocked by a non-manifold edge the walk takes any unused boundary edge at the vertex.
  std::size_t countBoundaryLoops() {
    std::vector<std::size_t> boundary;
    for (std::size_t h = 0; h < mate_.size(); ++h) {
      if (mate_[h] == kBoundary) boundary.push_back(h);
    }
    if (boundary.empty()) return 0;
    buildBoundaryIncidence(boundary);
    used_.assign(mate_.size(), false);
    std::size_t loops = 0;
    for (const std::size_t start : boundary) {
      if (used_[start]) continue;
      ++loops;
      used_[start] = true;
      std::size_t current = start;
      std::size_t at = to(start);
      while (true) {
        std::size_t next = rotateToBoundary(current, at);
        if (next == start) break;  // the loop closed
        if (next == kBoundary || used_[next]) next = anyUnusedBoundaryAt(at);
        if (next == kBoundary) break;  // an open chain ends (only next to non-manifold edges)
        used_[next] = true;
        at = from(next) == at ? to(next) : from(next);
        current = next;
      }
    }
    return loops;
  }

 private:
  std::size_t corner(std::size_t halfEdge, std::size_t offset) const {
    return mesh_.triangles[halfEdge / 3][(halfEdge % 3 + offset) % 3];
  }

  /// The other side of halfEdge's triangle that touches `vertex` (one of halfEdge's ends).
  std::size_t otherSideAt(std::size_t halfEdge, std::size_t vertex) const {
    const std::size_t base = halfEdge - halfEdge % 3;
    const std::size_t side = halfEdge % 3;
    return base + (from(halfEdge) == vertex ? (side + 2) % 3 : (side + 1) % 3);
  }

  /// Turns around `vertex` from `halfEdge` across manifold edges until a boundary half-edge;
  /// kBoundary when a non-manifold edge blocks the way (or, defensively, the turn does not end).
  std::size_t rotateToBoundary(std::size_t halfEdge, std::size_t vertex) const {
    std::size_t side = otherSideAt(halfEdge, vertex);
    for (std::size_t steps = 0; steps <= mesh_.triangles.size(); ++steps) {
      const std::size_t across = mate_[side];
      if (across == kBoundary) return side;
      if (across == kNonManifold || across == kNotAnEdge) return kBoundary;
      side = otherSideAt(across, vertex);
    }
    return kBoundary;
  }

  void buildBoundaryIncidence(const std::vector<std::size_t>& boundary) {
    const std::size_t vertexCount = mesh_.positions.size();
    incidenceStart_.assign(vertexCount + 1, 0);
    for (const std::size_t h : boundary) {
      ++incidenceStart_[from(h) + 1];
      ++incidenceStart_[to(h) + 1];
    }
    std::partial_sum(incidenceStart_.begin(), incidenceStart_.end(), incidenceStart_.begin());
    incident_.resize(2 * boundary.size());
    std::vector<std::size_t> fill(incidenceStart_.begin(), incidenceStart_.end() - 1);
    for (const std::size_t h : boundary) {
      incident_[fill[from(h)]++] = h;
      incident_[fill[to(h)]++] = h;
    }
    cursor_.assign(incidenceStart_.begin(), incidenceStart_.end() - 1);
  }

  std::size_t anyUnusedBoundaryAt(std::size_t vertex) {
    std::size_t& position = cursor_[vertex];
    while (position < incidenceStart_[vertex + 1] && used_[incident_[position]]) ++position;
    return position < incidenceStart_[vertex + 1] ? incident_[position] : kBoundary;
  }

  const TriangleMesh& mesh_;
  std::vector<std::size_t> mate_;
  std::vector<bool> used_;
  std::vector<std::size_t> incidenceStart_;
  std::vector<std::size_t> incident_;
  std::vector<std::size_t> cursor_;
};

/// Counts the vertices some triangle references (unreferencedVertexCount in `report`) and returns
/// how many there are; `scale` becomes the squared bounding-box diagonal of those vertices.
std::size_t countReferencedVertices(const TriangleMesh& mesh, MeshReport& report, double& scale) {
  std::vector<bool> referenced(mesh.positions.size(), false);
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  std::size_t referencedCount = 0;
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    for (const Index v : triangle) {
      if (referenced[v]) continue;
      referenced[v] = true;
      ++referencedCount;
      low = low.cwiseMin(mesh.positions[v].cast<double>());
      high = high.cwiseMax(mesh.positions[v].cast<double>());
    }
  }
  report.unreferencedVertexCount = mesh.positions.size() - referencedCount;
  scale = referencedCount > 0 ? (high - low).squaredNorm() : 0.0;
  return referencedCount;
}

/// Counts the degenerate triangles (a repeated index, or area at most 1e-12 of `scale`) and
/// returns which have a repeated index (`collapsedCount` of them): those have no proper edges and
/// are left out of the topology.
std::vector<bool> findDegenerateTriangles(const TriangleMesh& mesh, double scale,
                                          MeshReport& report, std::size_t& collapsedCount) {
  std::vector<bool> collapsed(mesh.triangles.size(), false);
  collapsedCount = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const TriangleMesh::Triangle& triangle = mesh.triangles[t];
    if (triangle[0] == triangle[1] || triangle[1] == triangle[2] || triangle[2] == triangle[0]) {
      collapsed[t] = true;
      ++collapsedCount;
      ++report.degenerateTriangleCount;
      continue;
    }
    const Eigen::Vector3d a = mesh.positions[triangle[0]].cast<double>();
    const Eigen::Vector3d b = mesh.positions[triangle[1]].cast<double>();
    const Eigen::Vector3d c = mesh.positions[triangle[2]].cast<double>();
    if ((b - a).cross(c - a).norm() <= 1e-12 * scale) ++report.degenerateTriangleCount;
  }
  return collapsed;
}

/// The edge table: every half-edge of the triangles not `collapsed` keyed by its undirected edge,
/// sorted so equal edges are adjacent (and by half-edge within them).
std::vector<HalfEdgeKey> sortedHalfEdges(const TriangleMesh& mesh,
                                         const std::vector<bool>& collapsed,
                                         std::size_t collapsedCount) {
  const std::size_t triangleCount = mesh.triangles.size();
  std::vector<HalfEdgeKey> keys;
  keys.reserve(3 * (triangleCount - collapsedCount));
  for (std::size_t t = 0; t < triangleCount; ++t) {
    if (collapsed[t]) continue;
    for (std::size_t side = 0; side < 3; ++side) {
      const std::uint64_t a = mesh.triangles[t][side];
      const std::uint64_t b = mesh.triangles[t][(side + 1) % 3];
      const std::uint64_t edge = a < b ? (a << 32) | b : (b << 32) | a;
      keys.push_back({edge, 3 * t + side});
    }
  }
  tbb::parallel_sort(keys.begin(), keys.end(), [](const HalfEdgeKey& x, const HalfEdgeKey& y) {
    return x.edge < y.edge || (x.edge == y.edge && x.halfEdge < y.halfEdge);
  });
  return keys;
}

/// Edge-connected triangles and, per vertex, corners joined across the edges at that vertex (its
/// fans). Corner c = 3 * t + k is vertex k of triangle t.
struct Connectivity {
  explicit Connectivity(std::size_t triangleCount)
      : triangleSets(triangleCount), cornerSets(3 * triangleCount) {}
  DisjointSets triangleSets;
  DisjointSets cornerSets;
};

/// One undirected edge, the half-edges keys[begin..end): counts it by its number of users, fills
/// the mate table, and joins its triangles and the corners at its two ends.
void addEdge(const std::vector<HalfEdgeKey>& keys, std::size_t begin, std::size_t end,
             Topology& topology, Connectivity& connectivity, MeshReport& report) {
  const std::size_t users = end - begin;
  ++report.edgeCount;
  const std::size_t first = keys[begin].halfEdge;
  if (users == 1) {
    ++report.boundaryEdgeCount;
    topology.mate(first) = kBoundary;
  } else if (users == 2) {
    const std::size_t second = keys[begin + 1].halfEdge;
    topology.mate(first) = second;
    topology.mate(second) = first;
    if (topology.from(first) == topology.from(second)) ++report.inconsistentlyOrientedEdgeCount;
  } else {
    ++report.nonManifoldEdgeCount;
    for (std::size_t i = begin; i < end; ++i) topology.mate(keys[i].halfEdge) = kNonManifold;
  }
  const std::size_t firstFrom = topology.from(first);
  for (std::size_t i = begin + 1; i < end; ++i) {
    const std::size_t halfEdge = keys[i].halfEdge;
    connectivity.triangleSets.unite(first / 3, halfEdge / 3);
    const std::size_t fromCorner = halfEdge;
    const std::size_t toCorner = halfEdge - halfEdge % 3 + (halfEdge % 3 + 1) % 3;
    const std::size_t firstFromCorner = first;
    const std::size_t firstToCorner = first - first % 3 + (first % 3 + 1) % 3;
    const bool sameDirection = topology.from(halfEdge) == firstFrom;
    connectivity.cornerSets.unite(firstFromCorner, sameDirection ? fromCorner : toCorner);
    connectivity.cornerSets.unite(firstToCorner, sameDirection ? toCorner : fromCorner);
  }
}

/// Counts the connected components and the vertices with more than one fan.
void countComponentsAndFans(const TriangleMesh& mesh, const std::vector<bool>& collapsed,
                            const Connectivity& connectivity, MeshReport& report) {
  std::vector<std::uint32_t> fansAtVertex(mesh.positions.size(), 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (collapsed[t]) continue;
    if (connectivity.triangleSets.isRoot(t)) ++report.connectedComponentCount;
    for (std::size_t k = 0; k < 3; ++k) {
      if (connectivity.cornerSets.isRoot(3 * t + k)) ++fansAtVertex[mesh.triangles[t][k]];
    }
  }
  for (const std::uint32_t fans : fansAtVertex) {
    if (fans > 1) ++report.nonManifoldVertexCount;
  }
}

}  // namespace

std::string MeshReport::problems() const {
  std::string lines;
  if (triangleCount == 0) lines += "the mesh has no triangles\n";
  if (boundaryEdgeCount > 0) {
    lines += plural(boundaryEdgeCount, "boundary edge", "boundary edges") + " in " +
             plural(boundaryLoopCount, "loop", "loops") + " (the mesh is not closed)\n";
  }
  if (nonManifoldEdgeCount > 0) {
    lines += plural(nonManifoldEdgeCount, "non-manifold edge", "non-manifold edges") +
             " (shared by three or more triangles)\n";
  }
  if (nonManifoldVertexCount > 0) {
    lines += plural(nonManifoldVertexCount, "non-manifold vertex", "non-manifold vertices") +
             " (triangle fans that meet only at the vertex)\n";
  }
  if (inconsistentlyOrientedEdgeCount > 0) {
    lines += plural(inconsistentlyOrientedEdgeCount, "inconsistently oriented edge",
                    "inconsistently oriented edges") +
             " (neighbouring triangles wound in opposite directions)\n";
  }
  if (degenerateTriangleCount > 0) {
    lines += plural(degenerateTriangleCount, "degenerate triangle", "degenerate triangles") +
             " (a repeated vertex or zero area)\n";
  }
  return lines;
}

MeshReport validateMesh(const TriangleMesh& mesh) {
  detail::checkTriangleIndices(mesh, "cannot validate the mesh");
  const std::size_t triangleCount = mesh.triangles.size();
  MeshReport report;
  report.vertexCount = mesh.positions.size();
  report.triangleCount = triangleCount;

  double scale = 0.0;
  const std::size_t referencedCount = countReferencedVertices(mesh, report, scale);
  std::size_t collapsedCount = 0;
  const std::vector<bool> collapsed = findDegenerateTriangles(mesh, scale, report, collapsedCount);
  const std::vector<HalfEdgeKey> keys = sortedHalfEdges(mesh, collapsed, collapsedCount);

  Topology topology(mesh);
  for (std::size_t t = 0; t < triangleCount; ++t) {
    if (!collapsed[t]) continue;
    for (std::size_t side = 0; side < 3; ++side) topology.mate(3 * t + side) = kNotAnEdge;
  }
  Connectivity connectivity(triangleCount);
  for (std::size_t begin = 0; begin < keys.size();) {
    std::size_t end = begin + 1;
    while (end < keys.size() && keys[end].edge == keys[begin].edge) ++end;
    addEdge(keys, begin, end, topology, connectivity, report);
    begin = end;
  }
  countComponentsAndFans(mesh, collapsed, connectivity, report);

  report.boundaryLoopCount = topology.countBoundaryLoops();
  report.eulerCharacteristic = static_cast<long>(referencedCount) -
                               static_cast<long>(report.edgeCount) +
                               static_cast<long>(triangleCount - collapsedCount);
  report.closed = triangleCount > collapsedCount && report.boundaryEdgeCount == 0 &&
                  report.nonManifoldEdgeCount == 0;
  report.manifold = report.nonManifoldEdgeCount == 0 && report.nonManifoldVertexCount == 0;
  report.oriented = report.inconsistentlyOrientedEdgeCount == 0;
  return report;
}

}  // namespace d2vdb
