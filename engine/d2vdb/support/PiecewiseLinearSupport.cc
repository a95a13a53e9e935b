#include "d2vdb/support/PiecewiseLinearSupport.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>
#include <utility>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

using Index = SphericalTriangulation::Index;
using Triangle = SphericalTriangulation::Triangle;

std::uint64_t directedKey(Index from, Index to) {
  return (static_cast<std::uint64_t>(from) << 32) | to;
}

// Directed edge -> triangle containing it (with that direction).
std::unordered_map<std::uint64_t, std::size_t> directedEdges(const std::vector<Triangle>& tris) {
  std::unordered_map<std::uint64_t, std::size_t> edges;
  edges.reserve(tris.size() * 3);
  for (std::size_t t = 0; t < tris.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      edges[directedKey(tris[t][static_cast<std::size_t>(k)],
                        tris[t][static_cast<std::size_t>((k + 1) % 3)])] = t;
    }
  }
  return edges;
}

// The corner of `tri` that is neither a nor b.
Index opposite(const Triangle& tri, Index a, Index b) {
  for (const Index v : tri) {
    if (v != a && v != b) return v;
  }
  return tri[0];
}

double orientation(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return a.dot(b.cross(c));
}

}  // namespace

PiecewiseLinearSupport::PiecewiseLinearSupport(SphericalTriangulation triangulation,
                                               std::vector<double> values)
    : triangulation_(std::move(triangulation)), values_(std::move(values)) {
  validateSphericalTriangulation(triangulation_, "the piecewise-linear support's triangulation");
  if (values_.size() != triangulation_.normals.size()) {
    throw InputError("a piecewise-linear support function needs one value per vertex: " +
                     std::to_string(triangulation_.normals.size()) + " vertices, " +
                     std::to_string(values_.size()) + " values");
  }
  for (std::size_t i = 0; i < values_.size(); ++i) {
    if (!std::isfinite(values_[i])) {
      throw InputError("piecewise-linear support value " + std::to_string(i) + " is not finite");
    }
  }
}

PiecewiseLinearSupport PiecewiseLinearSupport::sample(
    const std::function<double(const Eigen::Vector3d&)>& h, SphericalTriangulation triangulation) {
  validateSphericalTriangulation(triangulation, "the piecewise-linear support's triangulation");
  std::vector<double> values;
  values.reserve(triangulation.normals.size());
  for (const Eigen::Vector3d& n : triangulation.normals) values.push_back(h(n));
  return PiecewiseLinearSupport(std::move(triangulation), std::move(values));
}

PiecewiseLinearSupport PiecewiseLinearSupport::offset(double distance) const {
  if (!std::isfinite(distance)) throw InputError("the offset distance is not finite");
  std::vector<double> moved = values_;
  for (double& value : moved) value += distance;
  return PiecewiseLinearSupport(triangulation_, std::move(moved));
}

Eigen::Vector3d PiecewiseLinearSupport::dualVertex(std::size_t triangle) const {
  const Triangle& tri = triangulation_.triangles.at(triangle);
  const Eigen::Vector3d& a = triangulation_.normals[tri[0]];
  const Eigen::Vector3d& b = triangulation_.normals[tri[1]];
  const Eigen::Vector3d& c = triangulation_.normals[tri[2]];
  const double det = orientation(a, b, c);
  if (!(std::abs(det) >= 1e-14)) {
    throw InputError("triangle " + std::to_string(triangle) +
                     " of the piecewise-linear support has linearly dependent normals, so its "
                     "three planes do not meet in a point");
  }
  return (values_[tri[0]] * b.cross(c) + values_[tri[1]] * c.cross(a) +
          values_[tri[2]] * a.cross(b)) /
         det;
}

std::vector<Eigen::Vector3d> PiecewiseLinearSupport::dualVertices() const {
  std::vector<Eigen::Vector3d> vertices(triangulation_.triangles.size());
  for (std::size_t t = 0; t < vertices.size(); ++t) vertices[t] = dualVertex(t);
  return vertices;
}

TriangleMesh PiecewiseLinearSupport::dualPolyhedron() const {
  const std::vector<Eigen::Vector3d> vertices = dualVertices();
  const auto edges = directedEdges(triangulation_.triangles);
  // One triangle per vertex to start its fan from.
  std::vector<std::size_t> start(triangulation_.normals.size(), triangulation_.triangles.size());
  for (std::size_t t = 0; t < triangulation_.triangles.size(); ++t) {
    for (const Index v : triangulation_.triangles[t]) {
      if (start[v] == triangulation_.triangles.size()) start[v] = t;
    }
  }
  TriangleMesh mesh;
  mesh.positions.reserve(vertices.size());
  for (const Eigen::Vector3d& v : vertices) mesh.positions.push_back(v.cast<float>());
  for (Index i = 0; i < static_cast<Index>(triangulation_.normals.size()); ++i) {
    if (start[i] == triangulation_.triangles.size()) continue;
    // Walk counter-clockwise about n_i: from (i, a, b) to the triangle with directed edge i -> b.
    std::vector<std::size_t> fan;
    std::size_t t = start[i];
    bool closed = false;
    for (std::size_t guard = 0; guard <= triangulation_.triangles.size(); ++guard) {
      fan.push_back(t);
      const Triangle& tri = triangulation_.triangles[t];
      int k = 0;
      while (tri[static_cast<std::size_t>(k)] != i) ++k;
      const Index b = tri[static_cast<std::size_t>((k + 2) % 3)];
      const auto next = edges.find(directedKey(i, b));
      if (next == edges.end()) break;
      t = next->second;
      if (t == start[i]) {
        closed = true;
        break;
      }
    }
    if (!closed || fan.size() < 3) continue;
    for (std::size_t k = 1; k + 1 < fan.size(); ++k) {
      mesh.triangles.push_back({static_cast<TriangleMesh::Index>(fan[0]),
                                static_cast<TriangleMesh::Index>(fan[k]),
                                static_cast<TriangleMesh::Index>(fan[k + 1])});
    }
  }
  return mesh;
}

std::size_t PiecewiseLinearSupport::foldedEdges() const {
  const auto edges = directedEdges(triangulation_.triangles);
  double scale = 0.0;
  for (const double value : values_) scale = std::max(scale, std::abs(value));
  const double tolerance = 1e-12 * scale;
  std::size_t folded = 0;
  for (const auto& entry : edges) {
    const auto from = static_cast<Index>(entry.first >> 32);
    const auto to = static_cast<Index>(entry.first & 0xffffffffu);
    if (from > to) continue;  // each undirected edge once
    const auto other = edges.find(directedKey(to, from));
    if (other == edges.end()) continue;  // boundary
    const Index l = opposite(triangulation_.triangles[other->second], from, to);
    const Eigen::Vector3d v = dualVertex(entry.second);
    if (triangulation_.normals[l].dot(v) > values_[l] + tolerance) ++folded;
  }
  return folded;
}

std::size_t PiecewiseLinearSupport::removeSwallowtails() {
  std::vector<Triangle>& tris = triangulation_.triangles;
  const std::vector<Eigen::Vector3d>& normals = triangulation_.normals;
  auto edges = directedEdges(tris);
  double scale = 0.0;
  for (const double value : values_) scale = std::max(scale, std::abs(value));
  const double tolerance = 1e-12 * scale;
  std::vector<std::pair<Index, Index>> stack;
  for (const auto& entry : edges) {
    const auto from = static_cast<Index>(entry.first >> 32);
    const auto to = static_cast<Index>(entry.first & 0xffffffffu);
    if (from < to) stack.emplace_back(from, to);
  }
  std::sort(stack.begin(), stack.end());  // deterministic order
  std::size_t flips = 0;
  const std::size_t limit = 100 * tris.size() + 100;
  while (!stack.empty() && flips < limit) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    const auto first = edges.find(directedKey(i, j));
    const auto second = edges.find(directedKey(j, i));
    if (first == edges.end() || second == edges.end()) continue;
    const std::size_t t1 = first->second;   // (i, j, k)
    const std::size_t t2 = second->second;  // (j, i, l)
    const Index k = opposite(tris[t1], i, j);
    const Index l = opposite(tris[t2], i, j);
    if (k == l || edges.count(directedKey(k, l)) != 0) continue;
    const Eigen::Vector3d v = dualVertex(t1);
    if (!(normals[l].dot(v) > values_[l] + tolerance)) continue;
    // New triangles (i, l, k) and (l, j, k) must stay counter-clockwise on the sphere.
    if (!(orientation(normals[i], normals[l], normals[k]) > 0.0) ||
        !(orientation(normals[l], normals[j], normals[k]) > 0.0)) {
      continue;
    }
    edges.erase(directedKey(i, j));
    edges.erase(directedKey(j, i));
    tris[t1] = {i, l, k};
    tris[t2] = {l, j, k};
    edges[directedKey(i, l)] = t1;
    edges[directedKey(l, k)] = t1;
    edges[directedKey(k, i)] = t1;
    edges[directedKey(l, j)] = t2;
    edges[directedKey(j, k)] = t2;
    edges[directedKey(k, l)] = t2;
    ++flips;
    stack.emplace_back(std::min(i, l), std::max(i, l));
    stack.emplace_back(std::min(l, j), std::max(l, j));
    stack.emplace_back(std::min(j, k), std::max(j, k));
    stack.emplace_back(std::min(k, i), std::max(k, i));
  }
  if (flips >= limit) {
    throw RuntimeFailure("edge flipping did not terminate after " + std::to_string(limit) +
                         " flips: the piecewise-linear support is not convex data");
  }
  return flips;
}

}  // namespace d2vdb
