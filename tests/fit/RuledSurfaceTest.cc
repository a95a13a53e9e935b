// Rulings of ruled surfaces: straight segments that lie on the surface, at the knots and samples.
#include "d2vdb/fit/RuledSurface.h"

#include <gtest/gtest.h>

#include "d2vdb/core/Error.h"
#include "d2vdb/fit/InitialSurface.h"

namespace d2vdb {
namespace {

TEST(RuledSurface, RulingsLieOnTheSurfaceAtKnotsAndSamples) {
  // A (1, 3) surface between two different cubic curves, closed in v, 3 rows (two pieces).
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 6; ++j) {
      const double a = 6.283185307179586 * j / 6 + 0.3 * i;
      points.emplace_back((1 + 0.2 * i) * std::cos(a), (1 + 0.1 * j) * std::sin(a), i);
    }
  }
  const BSplineSurface surface(KnotVector::clamped(1, 3, {0, 1}),
                               KnotVector::periodic(3, 6, {0, 1}), points, false, true);
  const std::vector<Ruling> rulings = surfaceRulings(surface, 2);
  ASSERT_EQ(rulings.size(), 6u * 3u * 2u);  // 6 spans x (knot + 2 samples), 2 pieces
  for (const Ruling& ruling : rulings) {
    const double u0 = 0.5 * ruling.piece, u1 = u0 + 0.5;
    for (const double t : {0.0, 0.3, 1.0}) {
      const Eigen::Vector3d onLine = (1 - t) * ruling.start + t * ruling.end;
      EXPECT_LT((surface.evaluate((1 - t) * u0 + t * u1, ruling.v) - onLine).norm(), 1e-14);
    }
  }
  EXPECT_THROW(surfaceRulings(planeSheet(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(),
                                         Eigen::Vector3d::UnitY(), SurfaceLayout{}),
                              2),
               InputError);
}

}  // namespace
}  // namespace d2vdb
