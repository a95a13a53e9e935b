#include "d2vdb/manifold/HalfEdgeMesh.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/MeshValidation.h"

namespace d2vdb {
namespace {

using Index = HalfEdgeMesh::Index;

constexpr Index kNoTwin = std::numeric_limits<Index>::max();
constexpr std::size_t kNamedExamples = 3;

std::uint64_t directedKey(Index from, Index to) {
  return (static_cast<std::uint64_t>(from) << 32) | static_cast<std::uint64_t>(to);
}

std::string edgeName(Index a, Index b) {
  return "(" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
}

/// The validation report's problems on one line ("; " between them).
std::string reportSummary(const std::vector<Eigen::Vector3d>& positions,
                          const std::vector<TriangleMesh::Triangle>& triangles) {
  TriangleMesh mesh;
  mesh.positions.reserve(positions.size());
  for (const Eigen::Vector3d& p : positions) mesh.positions.push_back(p.cast<float>());
  mesh.triangles = triangles;
  std::string problems = validateMesh(mesh).problems();
  while (!problems.empty() && problems.back() == '\n') problems.pop_back();
  std::replace(problems.begin(), problems.end(), '\n', ';');
  std::string spaced;
  for (const char c : problems) {
    spaced += c;
    if (c == ';') spaced += ' ';
  }
  return spaced;
}

[[noreturn]] void refuse(const std::vector<Eigen::Vector3d>& positions,
                         const std::vector<TriangleMesh::Triangle>& triangles,
                         const std::string& named) {
  std::string summary = reportSummary(positions, triangles);
  std::string message = "the mesh is not a closed, consistently oriented 2-manifold";
  if (!summary.empty()) message += " (" + summary + ")";
  message += ": " + named;
  throw InputError(message);
}

/// "N <noun><what>, the first a, b, c": the count of `items` with the singular or plural noun,
/// then the first kNamedExamples of them by name(item).
template <typename Item, typename Name>
std::string namedExamples(const std::vector<Item>& items, const char* singular, const char* plural,
                          const char* what, const Name& name) {
  std::string named =
      std::to_string(items.size()) + (items.size() == 1 ? singular : plural) + what + "the first ";
  for (std::size_t i = 0; i < std::min(items.size(), kNamedExamples); ++i) {
    named += (i == 0 ? "" : ", ") + name(items[i]);
  }
  return named;
}

/// InputError unless there are triangles, few enough for 32-bit half-edge indices, every
/// position is finite and every triangle names three distinct existing vertices.
void requireIndexedTriangles(const std::vector<Eigen::Vector3d>& positions,
                             const std::vector<TriangleMesh::Triangle>& triangles) {
  const std::size_t vertexCount = positions.size();
  const std::size_t faceCount = triangles.size();
  if (faceCount == 0) throw InputError("the mesh has no triangles");
  if (faceCount > (std::numeric_limits<Index>::max() - 3) / 3) {
    throw InputError("the mesh has too many triangles (" + std::to_string(faceCount) +
                     ") for 32-bit half-edge indices");
  }
  for (std::size_t v = 0; v < vertexCount; ++v) {
    if (!positions[v].allFinite()) {
      throw InputError("vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
  }
  for (std::size_t f = 0; f < faceCount; ++f) {
    const TriangleMesh::Triangle& t = triangles[f];
    for (const Index v : t) {
      if (v >= vertexCount) {
        throw InputError("triangle " + std::to_string(f) + " references vertex " +
                         std::to_string(v) + ", but the mesh has " + std::to_string(vertexCount) +
                         " vertices");
      }
    }
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      throw InputError("triangle " + std::to_string(f) + " repeats a vertex (" +
                       std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " +
                       std::to_string(t[2]) + "): a degenerate triangle has no smooth surface");
    }
  }
}

/// A directed edge's key (from, to) and its half-edge.
using DirectedEdge = std::pair<std::uint64_t, Index>;

/// The directed edges of `mesh`'s half-edges sorted by (from, to); ties (a directed edge used
/// twice) by half-edge.
std::vector<DirectedEdge> sortedDirectedEdges(const HalfEdgeMesh& mesh) {
  std::vector<DirectedEdge> keys(mesh.halfEdgeCount());
  tbb::parallel_for(std::size_t{0}, keys.size(), [&](std::size_t h) {
    keys[h] = {directedKey(mesh.from(static_cast<Index>(h)), mesh.to(static_cast<Index>(h))),
               static_cast<Index>(h)};
  });
  tbb::parallel_sort(keys.begin(), keys.end());
  return keys;
}

/// Sets twin[h] for every half-edge h whose directed edge is used once and whose opposite
/// directed edge exists (`keys` from sortedDirectedEdges). Returns the other edges (smaller
/// vertex first), sorted, each once.
std::vector<std::pair<Index, Index>> matchTwins(const HalfEdgeMesh& mesh,
                                                const std::vector<DirectedEdge>& keys,
                                                std::vector<Index>& twin) {
  std::vector<std::pair<Index, Index>> offending;
  const std::size_t halfEdgeCount = keys.size();
  for (std::size_t i = 0; i < halfEdgeCount; ++i) {
    const Index h = keys[i].second;
    const Index from = mesh.from(h), to = mesh.to(h);
    const bool repeated = (i > 0 && keys[i - 1].first == keys[i].first) ||
                          (i + 1 < halfEdgeCount && keys[i + 1].first == keys[i].first);
    const std::uint64_t wanted = directedKey(to, from);
    const auto found = std::lower_bound(keys.begin(), keys.end(), std::make_pair(wanted, Index{0}));
    const bool hasTwin = found != keys.end() && found->first == wanted;
    if (repeated || !hasTwin) {
      offending.emplace_back(std::min(from, to), std::max(from, to));
    } else {
      twin[h] = found->second;
    }
  }
  std::sort(offending.begin(), offending.end());
  offending.erase(std::unique(offending.begin(), offending.end()), offending.end());
  return offending;
}

/// Walks the fan of outgoing half-edges from `start` (h to twin(prev(h))), writing the k-th
/// to ring[k] and k to ringIndex[h], for at most `size` half-edges. True when the walk closes
/// after exactly `size` of them (the vertex's triangles form one fan).
bool walkRing(const std::vector<Index>& twin, Index start, std::size_t size, Index* ring,
              std::vector<int>& ringIndex) {
  std::size_t count = 0;
  Index h = start;
  do {
    if (count == size) break;  // the walk does not close within the fan size
    ring[count] = h;
    ringIndex[h] = static_cast<int>(count);
    ++count;
    h = twin[HalfEdgeMesh::prev(h)];
  } while (h != start);
  return h == start && count == size;
}

/// Diagonal length of the bounding box of the vertices of nonzero degree.
double usedBoundingBoxDiagonal(const HalfEdgeMesh& mesh) {
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    if (mesh.degree(static_cast<Index>(v)) == 0) continue;
    low = low.cwiseMin(mesh.position(static_cast<Index>(v)));
    high = high.cwiseMax(mesh.position(static_cast<Index>(v)));
  }
  return (high - low).norm();
}

}  // namespace

HalfEdgeMesh::HalfEdgeMesh(const TriangleMesh& mesh) {
  positions_.reserve(mesh.positions.size());
  for (const Eigen::Vector3f& p : mesh.positions) positions_.push_back(p.cast<double>());
  triangles_ = mesh.triangles;
  build();
}

HalfEdgeMesh::HalfEdgeMesh(std::vector<Eigen::Vector3d> positions,
                           std::vector<TriangleMesh::Triangle> triangles)
    : positions_(std::move(positions)), triangles_(std::move(triangles)) {
  build();
}

void HalfEdgeMesh::build() {
  requireIndexedTriangles(positions_, triangles_);
  const std::vector<DirectedEdge> keys = sortedDirectedEdges(*this);

  // Twins; edges without one or used twice in one direction are named in the error.
  twin_.assign(halfEdgeCount(), kNoTwin);
  const std::vector<std::pair<Index, Index>> offending = matchTwins(*this, keys, twin_);
  if (!offending.empty()) {
    refuse(positions_, triangles_,
           namedExamples(offending, " edge", " edges", " without exactly one opposite half-edge, ",
                         [](const std::pair<Index, Index>& edge) {
                           return edgeName(edge.first, edge.second);
                         }));
  }

  // Vertex rings, counter-clockwise from the outgoing half-edge of smallest index.
  const std::size_t vertexCount = positions_.size();
  ringStart_.assign(vertexCount + 1, 0);
  for (const auto& key : keys) ++ringStart_[static_cast<std::size_t>(key.first >> 32) + 1];
  for (std::size_t v = 0; v < vertexCount; ++v) ringStart_[v + 1] += ringStart_[v];
  ring_.assign(halfEdgeCount(), 0);
  ringIndex_.assign(halfEdgeCount(), 0);
  std::vector<Index> badVertices;
  std::vector<Index> lowDegree;
  for (std::size_t v = 0; v < vertexCount; ++v) {
    const std::size_t begin = ringStart_[v];
    const std::size_t end = ringStart_[v + 1];
    if (begin == end) continue;
    Index start = keys[begin].second;
    for (std::size_t i = begin; i < end; ++i) start = std::min(start, keys[i].second);
    if (!walkRing(twin_, start, end - begin, ring_.data() + begin, ringIndex_)) {
      badVertices.push_back(static_cast<Index>(v));
    } else if (end - begin < 3) {
      lowDegree.push_back(static_cast<Index>(v));
    }
    maxDegree_ = std::max(maxDegree_, static_cast<int>(end - begin));
  }
  const auto number = [](Index vertex) { return std::to_string(vertex); };
  if (!badVertices.empty()) {
    refuse(positions_, triangles_,
           namedExamples(badVertices, " vertex", " vertices",
                         " whose triangles form more than one fan, ", number));
  }
  if (!lowDegree.empty()) {
    throw InputError(namedExamples(lowDegree, " vertex has", " vertices have",
                                   " fewer than three neighbours (two triangles folded onto each "
                                   "other), ",
                                   number));
  }
  diagonal_ = usedBoundingBoxDiagonal(*this);
}

}  // namespace d2vdb
