// The generated marching-cubes tables: every case closes up on the cell boundary, orientation.
#include <gtest/gtest.h>

#include <map>
#include <utility>

#include "d2vdb/contour/detail/CubeTables.h"

namespace d2vdb::detail {
namespace {

/// True when two cell edges lie on a common face.
bool shareFace(int a, int b) {
  for (int face = 0; face < kCubeFaces; ++face) {
    const auto corners = faceCorners(face);
    const auto onFace = [&](int edge) {
      int count = 0;
      for (int corner : corners)
        count += corner == edgeStartCorner(edge) || corner == edgeEndCorner(edge);
      return count == 2;
    };
    if (onFace(a) && onFace(b)) return true;
  }
  return false;
}

TEST(CubeTables, EveryCaseIsAClosedOrientedPatchOnTheCellBoundary) {
  const CubeTables& tables = CubeTables::instance();
  int ambiguousCases = 0, centerCases = 0;
  for (int caseIndex = 0; caseIndex < 256; ++caseIndex) {
    const int ambiguous = tables.ambiguousFaces(caseIndex);
    ambiguousCases += ambiguous != 0;
    for (int joined = 0; joined < 64; ++joined) {
      if ((joined & ~ambiguous) != 0) continue;
      const CellTriangulation& cell =
          tables.triangulation(caseIndex, static_cast<std::uint8_t>(joined));
      centerCases += cell.centerEdges != 0;
      // Directed edge counts: interior edges appear once each way; boundary edges (one face
      // segment) once in one direction only.
      std::map<std::pair<int, int>, int> directed;
      int usedEdges = 0;
      for (int t = 0; t < cell.triangleCount; ++t) {
        for (int i = 0; i < 3; ++i) {
          const int a = cell.edges[3 * t + i], b = cell.edges[3 * t + (i + 1) % 3];
          ASSERT_NE(a, b);
          ++directed[{a, b}];
          if (a != kCellCenter) usedEdges |= 1 << a;
        }
      }
      EXPECT_EQ(usedEdges, tables.crossedEdges(caseIndex)) << caseIndex;
      for (const auto& [edge, count] : directed) {
        EXPECT_EQ(count, 1) << caseIndex;
        const bool reverse = directed.count({edge.second, edge.first}) != 0;
        const bool boundary = edge.first != kCellCenter && edge.second != kCellCenter &&
                              shareFace(edge.first, edge.second);
        EXPECT_NE(reverse, boundary)
            << "case " << caseIndex << " edge " << edge.first << "-" << edge.second;
      }
    }
  }
  EXPECT_GT(ambiguousCases, 0);
  EXPECT_GT(centerCases, 0);
  EXPECT_EQ(tables.triangleCount(0, 0), 0);
  EXPECT_EQ(tables.triangleCount(255, 0), 0);
}

TEST(CubeTables, TrianglesFaceAwayFromInsideCorners) {
  // Corner 0 inside: the triangle through the x, y and z edges at corner 0, counter-clockwise
  // seen from outside (the right-hand normal points away from corner 0).
  const CellTriangulation& cell = CubeTables::instance().triangulation(1, 0);
  ASSERT_EQ(cell.triangleCount, 1);
  EXPECT_EQ(cell.edges[0], 0);
  EXPECT_EQ(cell.edges[1], 4);
  EXPECT_EQ(cell.edges[2], 8);
  // The complement has the opposite winding.
  const CellTriangulation& complement = CubeTables::instance().triangulation(254, 0);
  ASSERT_EQ(complement.triangleCount, 1);
  EXPECT_EQ(complement.edges[0], 0);
  EXPECT_EQ(complement.edges[1], 8);
  EXPECT_EQ(complement.edges[2], 4);
}

TEST(CubeTables, AmbiguousFaceDecisionChangesTopology) {
  // Corners 0 and 3 inside: face z = 0 is ambiguous. Separated: two triangles; joined: one band.
  const CubeTables& tables = CubeTables::instance();
  const int caseIndex = (1 << 0) | (1 << 3);
  EXPECT_EQ(tables.ambiguousFaces(caseIndex), 1 << 4);
  EXPECT_EQ(tables.triangleCount(caseIndex, 0), 2);
  EXPECT_EQ(tables.triangleCount(caseIndex, 1 << 4), 4);
}

}  // namespace
}  // namespace d2vdb::detail
