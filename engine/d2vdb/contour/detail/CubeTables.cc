// Generation of the marching-cubes tables from the face rule described in CubeTables.h.
#include "d2vdb/contour/detail/CubeTables.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>

namespace d2vdb::detail {
namespace {

/// The two axes other than `axis`, in increasing order.
std::array<int, 2> otherAxes(int axis) {
  if (axis == 0) return {1, 2};
  if (axis == 1) return {0, 2};
  return {0, 1};
}

int cornerAt(const std::array<int, 3>& offset) {
  return offset[0] | offset[1] << 1 | offset[2] << 2;
}

Eigen::Vector3d cornerPosition(int corner) {
  const auto offset = cornerOffset(corner);
  return {double(offset[0]), double(offset[1]), double(offset[2])};
}

Eigen::Vector3d edgeMidpoint(int edge) {
  return 0.5 * (cornerPosition(edgeStartCorner(edge)) + cornerPosition(edgeEndCorner(edge)));
}

/// Bit mask of the two faces an edge lies on.
unsigned edgeFaces(int edge) {
  const auto offset = cornerOffset(edgeStartCorner(edge));
  unsigned mask = 0;
  for (int axis : otherAxes(edgeAxis(edge))) mask |= 1u << (2 * axis + offset[axis]);
  return mask;
}

/// The edge joining two corners that differ in exactly one coordinate.
int edgeBetween(int cornerA, int cornerB) {
  for (int edge = 0; edge < kCubeEdges; ++edge) {
    const int start = edgeStartCorner(edge), end = edgeEndCorner(edge);
    if ((start == cornerA && end == cornerB) || (start == cornerB && end == cornerA)) return edge;
  }
  throw std::logic_error("CubeTables: corners are not adjacent");
}

/// Triangulates one closed contour (cell edges in winding order) into `out`.
void triangulateLoop(const std::vector<int>& loop, CellTriangulation& out) {
  const int n = static_cast<int>(loop.size());
  // Cost of a diagonal: prohibitive between two vertices on one cell face, else its length.
  const auto weight = [&](int i, int j) {
    if (j == i + 1 || (i == 0 && j == n - 1)) return 0.0;
    if (edgeFaces(loop[i]) & edgeFaces(loop[j])) return 1e6;
    return (edgeMidpoint(loop[i]) - edgeMidpoint(loop[j])).norm();
  };
  std::vector<double> cost(n * n, 0.0);
  std::vector<int> split(n * n, -1);
  for (int length = 2; length < n; ++length) {
    for (int i = 0; i + length < n; ++i) {
      const int j = i + length;
      double best = std::numeric_limits<double>::infinity();
      for (int m = i + 1; m < j; ++m) {
        const double candidate = cost[i * n + m] + cost[m * n + j] + weight(i, m) + weight(m, j);
        if (candidate < best) {
          best = candidate;
          split[i * n + j] = m;
        }
      }
      cost[i * n + j] = best;
    }
  }
  const auto emit = [&out](int a, int b, int c) {
    if (out.triangleCount >= kMaxCellTriangles) throw std::logic_error("CubeTables: overflow");
    const int base = 3 * out.triangleCount++;
    out.edges[base] = static_cast<std::uint8_t>(a);
    out.edges[base + 1] = static_cast<std::uint8_t>(b);
    out.edges[base + 2] = static_cast<std::uint8_t>(c);
  };
  if (cost[n - 1] >= 1e6) {
    // Every triangulation needs an in-face diagonal (some 8-, 9- and 12-sided contours): fan
    // around a vertex inside the cell instead.
    if (out.centerEdges != 0) throw std::logic_error("CubeTables: two centre vertices");
    for (int i = 0; i < n; ++i) {
      out.centerEdges |= static_cast<std::uint16_t>(1u << loop[i]);
      emit(kCellCenter, loop[i], loop[(i + 1) % n]);
    }
    return;
  }
  std::vector<std::pair<int, int>> pending{{0, n - 1}};
  while (!pending.empty()) {
    const auto [i, j] = pending.back();
    pending.pop_back();
    if (j - i < 2) continue;
    const int m = split[i * n + j];
    emit(loop[i], loop[m], loop[j]);
    pending.emplace_back(m, j);
    pending.emplace_back(i, m);
  }
}

/// Builds the triangulation of one case with the given face decisions.
CellTriangulation buildCase(int caseIndex, unsigned joinedFaces) {
  const auto inside = [caseIndex](int corner) { return ((caseIndex >> corner) & 1) != 0; };
  std::array<int, kCubeEdges> next;
  next.fill(-1);
  for (int face = 0; face < kCubeFaces; ++face) {
    const auto corners = faceCorners(face);
    std::array<int, 4> edges;  // edges[i] joins corners[i] and corners[i + 1]
    for (int i = 0; i < 4; ++i) edges[i] = edgeBetween(corners[i], corners[(i + 1) % 4]);
    std::vector<std::pair<int, int>> segments;
    std::vector<int> crossed;
    for (int i = 0; i < 4; ++i) {
      if (inside(corners[i]) != inside(corners[(i + 1) % 4])) crossed.push_back(edges[i]);
    }
    if (crossed.size() == 2) {
      segments.emplace_back(crossed[0], crossed[1]);
    } else if (crossed.size() == 4) {
      // Cut off the two corners that are not joined: the outside ones when the inside corners
      // are joined, the inside ones otherwise.
      const bool cutInside = ((joinedFaces >> face) & 1) == 0;
      for (int i = 0; i < 4; ++i) {
        if (inside(corners[i]) == cutInside) segments.emplace_back(edges[(i + 3) % 4], edges[i]);
      }
    }
    const int axis = face / 2;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    normal[axis] = face % 2 == 0 ? -1.0 : 1.0;
    for (auto [from, to] : segments) {
      // Orient so that normal x direction points to the outside corners.
      const Eigen::Vector3d start = edgeMidpoint(from);
      const Eigen::Vector3d direction = edgeMidpoint(to) - start;
      const int probe = edgeStartCorner(from);
      const double side = normal.cross(direction).dot(cornerPosition(probe) - start);
      if ((side > 0) == inside(probe)) std::swap(from, to);
      if (next[from] != -1) throw std::logic_error("CubeTables: inconsistent segments");
      next[from] = to;
    }
  }
  CellTriangulation result;
  std::array<bool, kCubeEdges> visited{};
  for (int edge = 0; edge < kCubeEdges; ++edge) {
    const bool crossed = inside(edgeStartCorner(edge)) != inside(edgeEndCorner(edge));
    if (crossed != (next[edge] != -1)) throw std::logic_error("CubeTables: open contour");
    if (!crossed || visited[edge]) continue;
    std::vector<int> loop;
    for (int current = edge; !visited[current]; current = next[current]) {
      visited[current] = true;
      loop.push_back(current);
    }
    triangulateLoop(loop, result);
  }
  return result;
}

}  // namespace

int edgeStartCorner(int edge) {
  const int axis = edgeAxis(edge), j = edge % 4;
  const auto others = otherAxes(axis);
  std::array<int, 3> offset{0, 0, 0};
  offset[others[0]] = j & 1;
  offset[others[1]] = j >> 1;
  return cornerAt(offset);
}

int edgeEndCorner(int edge) {
  return edgeStartCorner(edge) | (1 << edgeAxis(edge));
}

std::array<int, 4> faceCorners(int face) {
  const int axis = face / 2;
  const auto others = otherAxes(axis);
  std::array<int, 4> corners{};
  const std::array<std::array<int, 2>, 4> cycle{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
  for (int i = 0; i < 4; ++i) {
    std::array<int, 3> offset{0, 0, 0};
    offset[axis] = face % 2;
    offset[others[0]] = cycle[i][0];
    offset[others[1]] = cycle[i][1];
    corners[i] = cornerAt(offset);
  }
  return corners;
}

CubeTables::CubeTables() {
  for (int caseIndex = 0; caseIndex < 256; ++caseIndex) {
    const auto inside = [caseIndex](int corner) { return ((caseIndex >> corner) & 1) != 0; };
    for (int edge = 0; edge < kCubeEdges; ++edge) {
      if (inside(edgeStartCorner(edge)) != inside(edgeEndCorner(edge))) {
        crossedEdges_[caseIndex] |= static_cast<std::uint16_t>(1u << edge);
      }
    }
    for (int face = 0; face < kCubeFaces; ++face) {
      const auto c = faceCorners(face);
      if (inside(c[0]) == inside(c[2]) && inside(c[1]) == inside(c[3]) &&
          inside(c[0]) != inside(c[1])) {
        ambiguousFaces_[caseIndex] |= static_cast<std::uint8_t>(1u << face);
      }
    }
    offset_[caseIndex] = static_cast<std::uint32_t>(entries_.size());
    const int ambiguousCount = __builtin_popcount(ambiguousFaces_[caseIndex]);
    for (unsigned combination = 0; combination < (1u << ambiguousCount); ++combination) {
      // Expand the compressed decision bits onto the ambiguous faces.
      unsigned joined = 0;
      int bit = 0;
      for (int face = 0; face < kCubeFaces; ++face) {
        if ((ambiguousFaces_[caseIndex] >> face) & 1)
          joined |= ((combination >> bit++) & 1) << face;
      }
      entries_.push_back(buildCase(caseIndex, joined));
    }
  }
}

unsigned CubeTables::compress(int caseIndex, std::uint8_t joinedFaces) const {
  const unsigned ambiguous = ambiguousFaces_[caseIndex];
  if (ambiguous == 0) return 0;
  unsigned result = 0;
  int bit = 0;
  for (int face = 0; face < kCubeFaces; ++face) {
    if ((ambiguous >> face) & 1) result |= ((joinedFaces >> face) & 1u) << bit++;
  }
  return result;
}

const CubeTables& CubeTables::instance() {
  static const CubeTables tables;
  return tables;
}

}  // namespace d2vdb::detail
