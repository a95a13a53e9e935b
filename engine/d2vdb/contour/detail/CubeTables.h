// Marching-cubes case tables, generated at start-up from a topological rule (no copied tables).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace d2vdb::detail {

/// Geometry conventions of a unit cell (shared by the tables and the extractor):
/// - corner c (0..7) sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1);
/// - edge e (0..11) runs along axis e / 4 (0 = x, 1 = y, 2 = z) from the corner whose two other
///   coordinates are (j & 1, j >> 1) with j = e % 4, taken in increasing axis order
///   (x-edges: (y, z); y-edges: (x, z); z-edges: (x, y));
/// - face f (0..5) is the side f % 2 (0 = low, 1 = high) of axis f / 2.
/// A corner is "inside" when its value is below the iso-value (a value equal to it is outside).
/// The case index of a cell has bit c set when corner c is inside.
inline constexpr int kCubeCorners = 8;
inline constexpr int kCubeEdges = 12;
inline constexpr int kCubeFaces = 6;
/// At most this many triangles per cell, whatever the case and face decisions.
inline constexpr int kMaxCellTriangles = 12;

/// Offset (0 or 1 per axis) of corner `corner`.
constexpr std::array<int, 3> cornerOffset(int corner) {
  return {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
}
/// Axis (0, 1, 2) an edge runs along.
constexpr int edgeAxis(int edge) {
  return edge / 4;
}
/// The corner an edge starts from (its lower end along the edge axis).
int edgeStartCorner(int edge);
/// The corner an edge ends at (start corner + one along the edge axis).
int edgeEndCorner(int edge);
/// The four corners of a face in cyclic order around it.
std::array<int, 4> faceCorners(int face);

/// Code standing for the cell's centre vertex in CellTriangulation::edges.
inline constexpr int kCellCenter = 12;

/// The triangulation of one cell: triangles as triples of cell edges (each edge stands for the
/// mesh vertex on it, kCellCenter for a vertex inside the cell), wound counter-clockwise seen from
/// outside (the side above the iso-value).
struct CellTriangulation {
  std::uint8_t triangleCount = 0;
  /// Bit e set for the edges of the contour fanned around the centre vertex (0: no centre
  /// vertex). The centre vertex sits at the mean of those edges' vertices.
  std::uint16_t centerEdges = 0;
  std::array<std::uint8_t, 3 * kMaxCellTriangles> edges{};
};

/// The tables for all 256 sign cases, each with every resolution of its ambiguous faces.
///
/// Ambiguity resolution (documented rule): a face is ambiguous when its diagonal corners have
/// equal signs and adjacent corners different ones. Its inside corners are joined across the face
/// when the bilinear interpolant's saddle lies inside, which for values relative to the iso-value
/// (a, c on the inside diagonal, b, d on the outside one) is the asymptotic decider a*c > b*d;
/// otherwise (also on a tie) they are separated. Both cells sharing a face evaluate the same
/// products of the same values, so they always agree. Inside the cell, every closed contour the
/// face segments form on the cell's boundary bounds its own disc (no tunnels): a consistent
/// interior rule that keeps the surface closed and 2-manifold. Each disc is triangulated without
/// diagonals between two vertices of one cell face (such an edge could be shared by four
/// triangles), choosing the shortest diagonals among those; the few contours (8, 9 or 12 sides)
/// that admit no such triangulation are fanned around one extra vertex inside the cell.
class CubeTables {
 public:
  /// The process-wide tables (built on first use, thread-safe).
  static const CubeTables& instance();

  /// Bit f is set when face f is ambiguous in case `caseIndex`.
  std::uint8_t ambiguousFaces(int caseIndex) const { return ambiguousFaces_[caseIndex]; }

  /// Bit e is set when edge e is crossed (its corners differ) in case `caseIndex`.
  std::uint16_t crossedEdges(int caseIndex) const { return crossedEdges_[caseIndex]; }

  /// The triangulation of `caseIndex` with the decisions `joinedFaces` for its ambiguous faces:
  /// bit f set means the inside corners of ambiguous face f are joined. Bits of faces that are
  /// not ambiguous are ignored.
  const CellTriangulation& triangulation(int caseIndex, std::uint8_t joinedFaces) const {
    return entries_[offset_[caseIndex] + compress(caseIndex, joinedFaces)];
  }

  /// The triangle count of triangulation(caseIndex, joinedFaces).
  int triangleCount(int caseIndex, std::uint8_t joinedFaces) const {
    return triangulation(caseIndex, joinedFaces).triangleCount;
  }

  CubeTables();

 private:
  /// Index of the decision bits among the 2^k resolutions of the case's k ambiguous faces.
  unsigned compress(int caseIndex, std::uint8_t joinedFaces) const;

  std::array<std::uint8_t, 256> ambiguousFaces_{};
  std::array<std::uint16_t, 256> crossedEdges_{};
  std::array<std::uint32_t, 256> offset_{};
  std::vector<CellTriangulation> entries_;
};

}  // namespace d2vdb::detail
