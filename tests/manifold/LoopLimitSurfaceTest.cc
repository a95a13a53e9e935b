// The exact Loop limit surface against an independent reference: plain global Loop subdivision
// (edge map) followed by Loop's limit mask, which gives exact limit points at dyadic parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "ManifoldTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/LoopSubdivision.h"
#include "d2vdb/manifold/detail/LoopPatches.h"

namespace d2vdb {
namespace {

using test::DoubleMesh;

/// Largest distance between LoopLimitSurface and the reference at all dyadic points
/// (i, j) / 2^levels of every face, relative to the bounding-box diagonal.
double dyadicError(const DoubleMesh& coarse, int levels) {
  std::vector<DoubleMesh> hierarchy = {coarse};
  for (int level = 0; level < levels; ++level) {
    hierarchy.push_back(test::referenceSubdivide(hierarchy.back()));
  }
  const std::vector<Eigen::Vector3d> limits = test::referenceLimitPositions(hierarchy.back());
  const auto mesh = coarse.build();
  const LoopLimitSurface surface(mesh);
  const long scale = 1L << levels;
  double worst = 0.0;
  for (std::uint32_t f = 0; f < mesh->faceCount(); ++f) {
    for (long i = 0; i <= scale; ++i) {
      for (long j = 0; i + j <= scale; ++j) {
        FacePoint point{f, Eigen::Vector3d(double(scale - i - j) / scale, double(i) / scale,
                                           double(j) / scale)};
        const Eigen::Vector3d expected = limits[test::dyadicVertex(hierarchy, f, i, j, levels)];
        worst = std::max(worst, (surface.evaluate(point).position - expected).norm());
        Eigen::Vector3d batch;
        surface.positions(f, &point.bary, 1, &batch);
        EXPECT_LT((batch - surface.evaluate(point).position).norm(), 1e-15 * (1.0 + batch.norm()));
      }
    }
  }
  return worst / mesh->boundingBoxDiagonal();
}

TEST(LoopLimitSurface, RegularPatchMatchesSubdivisionOnATorus) {
  // Every vertex of degree 6: quartic box-spline patches only.
  const DoubleMesh mesh = test::torus(2.0, 0.7, 12, 8);
  const double error = dyadicError(mesh, 3);
  std::printf("torus 12 x 8, dyadic points 1/8: max error %.3g of the diagonal\n", error);
  EXPECT_LT(error, 1e-14);
}

TEST(LoopLimitSurface, OneExtraordinaryCornerMatchesSubdivision) {
  // Degrees 3..9: faces with one extraordinary corner (evaluated by subdividing the corner's
  // neighbourhood) and faces with more (evaluated on one subdivision step).
  const DoubleMesh mesh = test::mixedDegreeMesh();
  const double error = dyadicError(mesh, 3);
  std::printf("mixed degrees, dyadic points 1/8: max error %.3g of the diagonal\n", error);
  EXPECT_LT(error, 1e-14);
  const LoopLimitSurface surface(mesh.build());
  EXPECT_GT(surface.extraordinaryFaceCount(), 0u);
  EXPECT_GT(surface.subdividedFaceCount(), 0u);
}

TEST(LoopLimitSurface, AllExtraordinaryPlatonicSolids) {
  // Every face has three extraordinary corners (degree 3, 4 or 5).
  for (const DoubleMesh& mesh : {test::tetrahedron(), test::octahedron(), test::icosphere(0)}) {
    const double error = dyadicError(mesh, 4);
    EXPECT_LT(error, 1e-14);
    const LoopLimitSurface surface(mesh.build());
    EXPECT_EQ(surface.subdividedFaceCount(), mesh.triangles.size());
  }
}

TEST(LoopLimitSurface, RegularPatchReproducesLinearFunctionsAndSumsToOne) {
  const auto& matrix = detail::regularPatchMatrix();
  for (int r = 0; r < 15; ++r) EXPECT_NEAR(matrix.row(r).sum(), 1.0, 1e-15);
  // Control values a + b.x on the lattice give the same linear function on the patch: its Bézier
  // net holds the function at the net's domain points.
  for (int r = 0; r < 15; ++r) {
    double value = 0.0;
    for (int c = 0; c < 12; ++c) {
      const auto& l = detail::kRegularLattice[c];
      value += matrix(r, c) * (2.0 + 3.0 * l[0] - 5.0 * l[1]);
    }
    int j = 0;
    int k = 0;
    for (j = 0; j <= 4; ++j) {
      bool found = false;
      for (k = 0; k <= 4 - j; ++k) {
        if (detail::triangleIndex(4, j, k) == r) {
          found = true;
          break;
        }
      }
      if (found) break;
    }
    EXPECT_NEAR(value, 2.0 + 3.0 * j / 4.0 - 5.0 * k / 4.0, 1e-14);
  }
}

TEST(LoopLimitSurface, DerivativesMatchFiniteDifferences) {
  const DoubleMesh mesh = test::mixedDegreeMesh();
  const LoopLimitSurface surface(mesh.build());
  const double h = 1e-6;
  double worst = 0.0;
  for (std::uint32_t f = 0; f < surface.mesh().faceCount(); f += 7) {
    for (const Eigen::Vector3d& b :
         {Eigen::Vector3d(0.2, 0.3, 0.5), Eigen::Vector3d(0.9, 0.05, 0.05),
          Eigen::Vector3d(0.01, 0.98, 0.01), Eigen::Vector3d(0.3, 0.35, 0.35)}) {
      const SourceJet jet = surface.evaluate({f, b});
      ASSERT_TRUE(jet.derivativesValid);
      const auto at = [&](double d1, double d2) {
        return surface.evaluate({f, Eigen::Vector3d(b[0] - d1 - d2, b[1] + d1, b[2] + d2)})
            .position;
      };
      const Eigen::Vector3d f1 = (at(h, 0) - at(-h, 0)) / (2 * h);
      const Eigen::Vector3d f2 = (at(0, h) - at(0, -h)) / (2 * h);
      worst = std::max(worst, (f1 - jet.d1).norm() / jet.d1.norm());
      worst = std::max(worst, (f2 - jet.d2).norm() / jet.d2.norm());
    }
  }
  EXPECT_LT(worst, 1e-6);
}

TEST(LoopLimitSurface, LimitNormalIsTheLimitOfTheTangentPlane) {
  const DoubleMesh mesh = test::mixedDegreeMesh();
  const auto halfEdges = mesh.build();
  const LoopLimitSurface surface(halfEdges);
  for (HalfEdgeMesh::Index v = 0; v < halfEdges->vertexCount(); v += 5) {
    const HalfEdgeMesh::Index h = halfEdges->ring(v, 0);
    const int corner = static_cast<int>(h % 3);
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    b[corner] = 1.0;
    const FacePoint atVertex{HalfEdgeMesh::face(h), b};
    EXPECT_LT((surface.evaluate(atVertex).position - surface.limitPosition(v)).norm(), 1e-15);
    // Near the vertex the face's tangent plane approaches the limit normal (slowly where the
    // degree is high: the error shrinks like a ratio of subdivision eigenvalues per level).
    double previous = 2.0;
    for (const double t : {1e-4, 1e-8, 1e-12}) {
      b[corner] = 1.0 - 2.0 * t;
      b[(corner + 1) % 3] = t;
      b[(corner + 2) % 3] = t;
      const SourceJet near = surface.evaluate({HalfEdgeMesh::face(h), b});
      const double angle =
          std::acos(std::min(1.0, near.d1.cross(near.d2).normalized().dot(surface.limitNormal(v))));
      EXPECT_LE(angle, previous + 1e-7) << "vertex " << v << " t " << t;
      previous = angle;
    }
    EXPECT_LT(previous, 1e-2) << "vertex " << v;
  }
}

TEST(LoopLimitSurface, OneSubdivisionStepKeepsTheLimitSurface) {
  const DoubleMesh mesh = test::mixedDegreeMesh();
  const auto coarse = mesh.build();
  const auto fine = std::make_shared<const HalfEdgeMesh>(loopSubdivision(*coarse));
  EXPECT_EQ(fine->faceCount(), 4 * coarse->faceCount());
  const LoopLimitSurface a(coarse);
  const LoopLimitSurface b(fine);
  // Face f's sub-face 0 at (1/2, 1/2, 0) in fine coordinates is (3/4, 1/4, 0) in coarse ones.
  for (std::uint32_t f = 0; f < coarse->faceCount(); f += 3) {
    const Eigen::Vector3d p = a.evaluate({f, Eigen::Vector3d(0.75, 0.2, 0.05)}).position;
    const Eigen::Vector3d q = b.evaluate({4 * f, Eigen::Vector3d(0.5, 0.4, 0.1)}).position;
    EXPECT_LT((p - q).norm(), 1e-14);
  }
}

}  // namespace
}  // namespace d2vdb
