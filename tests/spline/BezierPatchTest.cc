// Bézier extraction of B-spline surfaces: every patch reproduces the surface on its knot cell,
// open (clamped, unclamped, repeated knots) and closed directions alike.
#include "d2vdb/spline/BezierPatch.h"

#include <gtest/gtest.h>

#include <random>

#include "d2vdb/core/Error.h"
#include "spline/SplineTestSupport.h"

namespace d2vdb {
namespace {

void expectPatchesReproduce(const BSplineSurface& surface, std::mt19937& rng) {
  const std::vector<BezierPatch> patches = toBezierPatches(surface);
  std::size_t cells =
      (surface.knotsU().breakpoints().size() - 1) * (surface.knotsV().breakpoints().size() - 1);
  ASSERT_EQ(patches.size(), cells);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const BezierPatch& patch : patches) {
    EXPECT_EQ(patch.controlPoints.size(),
              static_cast<std::size_t>((surface.degreeU() + 1) * (surface.degreeV() + 1)));
    for (int sample = 0; sample < 6; ++sample) {
      const double s = sample < 2 ? sample : unit(rng);
      const double t = sample < 2 ? 1 - sample : unit(rng);
      const Eigen::Vector3d expected =
          surface.evaluate(patch.intervalU.at(s), patch.intervalV.at(t));
      EXPECT_LT((patch.evaluate(s, t) - expected).norm(), 1e-12 * (1.0 + expected.norm()));
    }
  }
}

TEST(BezierPatch, PatchesReproduceOpenSurfaces) {
  std::mt19937 rng(8);
  for (int trial = 0; trial < 24; ++trial) {
    const int p = 1 + trial % 4;
    const int q = 1 + (trial / 4) % 4;
    KnotVector knotsU = test::randomKnotVector(rng, p, trial % 2 == 0);
    KnotVector knotsV = test::randomKnotVector(rng, q, trial % 3 == 0);
    const int count = knotsU.basisFunctionCount() * knotsV.basisFunctionCount();
    const BSplineSurface surface(std::move(knotsU), std::move(knotsV),
                                 test::randomPoints(rng, count));
    expectPatchesReproduce(surface, rng);
  }
}

TEST(BezierPatch, PatchesReproduceClosedSurfacesAcrossTheSeam) {
  std::mt19937 rng(9);
  for (const auto& [p, q, closedU, closedV] :
       {std::tuple{3, 3, true, true}, std::tuple{2, 3, true, false}, std::tuple{1, 3, false, true},
        std::tuple{3, 2, true, true}}) {
    const int nu = p + 4, nv = q + 3;
    KnotVector knotsU =
        closedU ? KnotVector::periodic(p, nu, {0.0, 2.0}) : KnotVector::clamped(p, nu, {0.0, 2.0});
    KnotVector knotsV = closedV ? KnotVector::periodic(q, nv, {-1.0, 1.0})
                                : KnotVector::clamped(q, nv, {-1.0, 1.0});
    const BSplineSurface surface(std::move(knotsU), std::move(knotsV),
                                 test::randomPoints(rng, nu * nv), closedU, closedV);
    expectPatchesReproduce(surface, rng);
  }
}

TEST(BezierPatch, ExtractionMatrixRowsSumToOneAndRejectEmptySpans) {
  const KnotVector knots(3, {0, 0, 0, 0, 0.3, 0.3, 0.7, 1, 1, 1, 1});
  for (int span = 3; span < knots.basisFunctionCount(); ++span) {
    if (!(knots[span] < knots[span + 1])) {
      EXPECT_THROW(bezierExtractionMatrix(knots, span), InputError);
      continue;
    }
    const Eigen::MatrixXd m = bezierExtractionMatrix(knots, span);
    for (int c = 0; c <= 3; ++c) EXPECT_NEAR(m.row(c).sum(), 1.0, 1e-14);
  }
  EXPECT_THROW(bezierExtractionMatrix(knots, 2), InputError);
}

}  // namespace
}  // namespace d2vdb
