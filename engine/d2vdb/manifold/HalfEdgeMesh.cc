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
  const std::size_t vertexCount = positions_.size();
  const std::size_t faceCount = triangles_.size();
  if (faceCount == 0) throw InputError("the mesh has no triangles");
  if (faceCount > (std::numeric_limits<Index>::max() - 3) / 3) {
    throw InputError("the mesh has too many triangles (" + std::to_string(faceCount) +
                     ") for 32-bit half-edge indices");
  }
  for (std::size_t v = 0; v < vertexCount; ++v) {
    if (!positions_[v].allFinite()) {
      throw InputError("vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
  }
  for (std::size_t f = 0; f < faceCount; ++f) {
    const TriangleMesh::Triangle& t = triangles_[f];
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

  // Directed edges sorted by (from, to); ties (a directed edge used twice) by half-edge.
  const std::size_t halfEdgeCount = 3 * faceCount;
  std::vector<std::pair<std::uint64_t, Index>> keys(halfEdgeCount);
  tbb::parallel_for(std::size_t{0}, halfEdgeCount, [&](std::size_t h) {
    keys[h] = {directedKey(from(static_cast<Index>(h)), to(static_cast<Index>(h))),
               static_cast<Index>(h)};
  });
  tbb::parallel_sort(keys.begin(), keys.end());

  // Twins; edges without one or used twice in one direction are named in the error.
  twin_.assign(halfEdgeCount, kNoTwin);
  std::vector<std::pair<Index, Index>> offending;
  for (std::size_t i = 0; i < halfEdgeCount; ++i) {
    const Index h = keys[i].second;
    const bool repeated = (i > 0 && keys[i - 1].first == keys[i].first) ||
                          (i + 1 < halfEdgeCount && keys[i + 1].first == keys[i].first);
    const std::uint64_t wanted = directedKey(to(h), from(h));
    const auto found = std::lower_bound(keys.begin(), keys.end(), std::make_pair(wanted, Index{0}));
    const bool hasTwin = found != keys.end() && found->first == wanted;
    if (repeated || !hasTwin) {
      offending.emplace_back(std::min(from(h), to(h)), std::max(from(h), to(h)));
    } else {
      twin_[h] = found->second;
    }
  }
  if (!offending.empty()) {
    std::sort(offending.begin(), offending.end());
    offending.erase(std::unique(offending.begin(), offending.end()), offending.end());
    std::string named = std::to_string(offending.size()) +
                        (offending.size() == 1 ? " edge" : " edges") +
                        " without exactly one opposite half-edge, the first ";
    for (std::size_t i = 0; i < std::min(offending.size(), kNamedExamples); ++i) {
      named += (i == 0 ? "" : ", ") + edgeName(offending[i].first, offending[i].second);
    }
    refuse(positions_, triangles_, named);
  }

  // Vertex rings, counter-clockwise from the outgoing half-edge of smallest index.
  ringStart_.assign(vertexCount + 1, 0);
  for (const auto& key : keys) ++ringStart_[static_cast<std::size_t>(key.first >> 32) + 1];
  for (std::size_t v = 0; v < vertexCount; ++v) ringStart_[v + 1] += ringStart_[v];
  ring_.assign(halfEdgeCount, 0);
  ringIndex_.assign(halfEdgeCount, 0);
  std::vector<Index> badVertices;
  std::vector<Index> lowDegree;
  for (std::size_t v = 0; v < vertexCount; ++v) {
    const std::size_t begin = ringStart_[v];
    const std::size_t end = ringStart_[v + 1];
    if (begin == end) continue;
    Index start = keys[begin].second;
    for (std::size_t i = begin; i < end; ++i) start = std::min(start, keys[i].second);
    std::size_t count = 0;
    Index h = start;
    do {
      if (count == end - begin) break;  // the walk does not close within the fan size
      ring_[begin + count] = h;
      ringIndex_[h] = static_cast<int>(count);
      ++count;
      h = twin_[prev(h)];
    } while (h != start);
    if (h != start || count != end - begin) {
      badVertices.push_back(static_cast<Index>(v));
    } else if (count < 3) {
      lowDegree.push_back(static_cast<Index>(v));
    }
    maxDegree_ = std::max(maxDegree_, static_cast<int>(end - begin));
  }
  if (!badVertices.empty()) {
    std::string named = std::to_string(badVertices.size()) +
                        (badVertices.size() == 1 ? " vertex" : " vertices") +
                        " whose triangles form more than one fan, the first ";
    for (std::size_t i = 0; i < std::min(badVertices.size(), kNamedExamples); ++i) {
      named += (i == 0 ? "" : ", ") + std::to_string(badVertices[i]);
    }
    refuse(positions_, triangles_, named);
  }
  if (!lowDegree.empty()) {
    std::string message = std::to_string(lowDegree.size()) +
                          (lowDegree.size() == 1 ? " vertex has" : " vertices have") +
                          " fewer than three neighbours (two triangles folded onto each other), "
                          "the first ";
    for (std::size_t i = 0; i < std::min(lowDegree.size(), kNamedExamples); ++i) {
      message += (i == 0 ? "" : ", ") + std::to_string(lowDegree[i]);
    }
    throw InputError(message);
  }

  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  for (std::size_t v = 0; v < vertexCount; ++v) {
    if (degree(static_cast<Index>(v)) == 0) continue;
    low = low.cwiseMin(positions_[v]);
    high = high.cwiseMax(positions_[v]);
  }
  diagonal_ = (high - low).norm();
}

}  // namespace d2vdb
