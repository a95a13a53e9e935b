// Charts and transition maps: round trips, agreement with the face-based maps, exact
// composition g_wu = g_wv o g_vu, and continuity across sector boundaries at degree-3 vertices
// (where the signed atan2 matters).
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "ManifoldTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/ChartAtlas.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/PseudoManifold.h"

namespace d2vdb {
namespace {

using Index = HalfEdgeMesh::Index;

/// Points of a face: an even barycentric sampling including edges and corners.
std::vector<Eigen::Vector3d> sampleBary() {
  std::vector<Eigen::Vector3d> points;
  const int n = 10;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; i + j <= n; ++j) {
      points.emplace_back(double(n - i - j) / n, double(i) / n, double(j) / n);
    }
  }
  return points;
}

int cornerOf(const HalfEdgeMesh& mesh, Index face, Index vertex) {
  for (int k = 0; k < 3; ++k) {
    if (mesh.corner(face, k) == vertex) return k;
  }
  return -1;
}

TEST(ChartAtlas, ChartsCoverEveryFaceAndRoundTrip) {
  for (const auto& m : {test::tetrahedron(), test::mixedDegreeMesh()}) {
    const auto mesh = m.build();
    const ChartAtlas atlas(*mesh);
    for (Index f = 0; f < mesh->faceCount(); ++f) {
      for (const Eigen::Vector3d& bary : sampleBary()) {
        bool covered = false;
        for (int corner = 0; corner < 3; ++corner) {
          if (!ChartAtlas::inChart(bary, corner)) continue;
          covered = true;
          const ChartPoint c = atlas.toChart({f, bary}, corner);
          EXPECT_LT(c.p.norm(), ChartAtlas::radius(mesh->degree(c.vertex)));
          const FacePoint back = atlas.fromChart(c);
          // The same point, possibly expressed in the neighbouring face when on an edge.
          const int k = cornerOf(*mesh, back.face, c.vertex);
          ASSERT_GE(k, 0);
          EXPECT_LT((atlas.toChart(back, k).p - c.p).norm(), 1e-14);
          if (back.face == f) {
            EXPECT_LT((back.bary - bary).norm(), 1e-14);
          }
        }
        EXPECT_TRUE(covered);
      }
    }
  }
}

TEST(ChartAtlas, TransitionsAgreeWithTheFaceMapsAndCompose) {
  const auto mesh = test::mixedDegreeMesh().build();
  const ChartAtlas atlas(*mesh);
  double worstAgreement = 0.0;
  double worstComposition = 0.0;
  int compositions = 0;
  for (Index f = 0; f < mesh->faceCount(); ++f) {
    for (const Eigen::Vector3d& bary : sampleBary()) {
      const FacePoint point{f, bary};
      for (int iu = 0; iu < 3; ++iu) {
        if (!ChartAtlas::inChart(bary, iu)) continue;
        const ChartPoint pu = atlas.toChart(point, iu);
        for (int iv = 0; iv < 3; ++iv) {
          if (iv == iu || !ChartAtlas::inChart(bary, iv)) continue;
          // The half-edge u -> v: in this face when v follows u, else its twin's face.
          const Index h = (iv == (iu + 1) % 3) ? 3 * f + static_cast<Index>(iu)
                                               : mesh->twin(3 * f + static_cast<Index>(iv));
          ASSERT_EQ(mesh->from(h), pu.vertex);
          const std::optional<Eigen::Vector2d> pv = atlas.transition(h, pu.p);
          ASSERT_TRUE(pv.has_value());
          worstAgreement = std::max(worstAgreement, (*pv - atlas.toChart(point, iv).p).norm());
          // Three charts: g_wu = g_wv o g_vu.
          const int iw = 3 - iu - iv;
          if (!ChartAtlas::inChart(bary, iw)) continue;
          const Index hw = (iw == (iu + 1) % 3) ? 3 * f + static_cast<Index>(iu)
                                                : mesh->twin(3 * f + static_cast<Index>(iw));
          const Index hvw = (iw == (iv + 1) % 3) ? 3 * f + static_cast<Index>(iv)
                                                 : mesh->twin(3 * f + static_cast<Index>(iw));
          const auto direct = atlas.transition(hw, pu.p);
          const auto composed = atlas.transition(hvw, *pv);
          ASSERT_TRUE(direct.has_value() && composed.has_value());
          worstComposition = std::max(worstComposition, (*direct - *composed).norm());
          ++compositions;
        }
      }
    }
  }
  std::printf("transitions: agreement %.3g, composition %.3g (%d triples)\n", worstAgreement,
              worstComposition, compositions);
  EXPECT_LT(worstAgreement, 1e-14);
  EXPECT_LT(worstComposition, 1e-14);
  EXPECT_GT(compositions, 1000);
}

TEST(ChartAtlas, TransitionDomainIsTheOverlap) {
  const auto mesh = test::octahedron().build();
  const ChartAtlas atlas(*mesh);
  const Index h = mesh->ring(0, 0);
  const double r = ChartAtlas::radius(4);
  const double edgeAngle = 0.0;  // ring 0 lies at angle 0
  // Beyond the disc, two sectors away from the edge, or too far from the neighbour: nothing.
  EXPECT_FALSE(atlas.transition(h, Eigen::Vector2d(1.01 * r, 0.0)).has_value());
  EXPECT_FALSE(atlas.transition(h, Eigen::Vector2d(0.0, -0.6 * r)).has_value());
  EXPECT_FALSE(atlas.transition(h, 0.05 * Eigen::Vector2d(std::cos(edgeAngle), 0.0)).has_value());
  EXPECT_TRUE(atlas.transition(h, Eigen::Vector2d(0.6 * r, 0.05)).has_value());
  EXPECT_THROW(atlas.fromChart({0, Eigen::Vector2d(r, 0.0)}), InputError);
}

TEST(ChartAtlas, SectorBoundariesAreContinuousAtDegreeThree) {
  // Tetrahedron: 120-degree sectors. Points just below and above each sector boundary (the ray
  // at angle 0 sits on the atan2 branch cut's far side) map to face points whose surface points
  // differ by O(eps).
  const auto mesh = test::tetrahedron().build();
  const LoopLimitSurface loop(mesh);
  const PseudoManifold pps(loop);
  const ChartAtlas& atlas = pps.atlas();
  const double eps = 1e-9;
  double worst = 0.0;
  for (Index v = 0; v < 4; ++v) {
    const double r = 0.6 * ChartAtlas::radius(3);
    for (int k = 0; k < 3; ++k) {
      const double angle = 2.0 * kPi * k / 3.0;
      const Eigen::Vector2d below(r * std::cos(angle - eps), r * std::sin(angle - eps));
      const Eigen::Vector2d above(r * std::cos(angle + eps), r * std::sin(angle + eps));
      const Eigen::Vector3d a = pps.position(atlas.fromChart({v, below}));
      const Eigen::Vector3d b = pps.position(atlas.fromChart({v, above}));
      worst = std::max(worst, (a - b).norm());
      EXPECT_NE(atlas.fromChart({v, below}).face, atlas.fromChart({v, above}).face);
    }
  }
  EXPECT_LT(worst, 1e-7);
}

}  // namespace
}  // namespace d2vdb
