// The chord-length re-parametrisation of the surface fitter's restart: a surface whose parameters
// are already spread by chord length (the circle-fit torus) keeps them; a crowded one (a torus
// fit's first iterations from wrong radii) gets an even spread and keeps its shape.
#include "d2vdb/fit/detail/SurfaceReparametrization.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "SurfaceFitTestSupport.h"
#include "d2vdb/fit/InitialSurface.h"
#include "d2vdb/fit/SurfaceFitter.h"

namespace d2vdb {
namespace {

double largestDistance(const BSplineSurface& surface, const test::ExactTorusTarget& torus) {
  double largest = 0.0;
  for (const Eigen::Vector3d& p : surface.sample(161, 97)) {
    largest = std::max(largest, torus.distance(p));
  }
  return largest;
}

TEST(SurfaceReparametrization, EvenSpreadIsKeptAndCrowdedSpreadIsEvenedOut) {
  const test::ExactTorusTarget torus(2.0, 0.5);
  const SurfaceLayout layout{3, 3, 16, 16, true, true};
  const BSplineSurface even =
      torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 2.0, 0.5, layout);
  const detail::Reparametrization kept = detail::chordLengthReparametrized(even);
  std::printf("circle-fit torus: shift %.3g, max distance %.3g -> %.3g\n", kept.shift,
              largestDistance(even, torus), largestDistance(kept.surface, torus));
  EXPECT_LT(kept.shift, 1e-3);
  double moved = 0.0;
  for (std::size_t i = 0; i < even.controlPoints().size(); ++i) {
    moved = std::max(moved, (kept.surface.controlPoints()[i] - even.controlPoints()[i]).norm());
  }
  EXPECT_LT(moved, 1e-3);

  // Three SDM iterations from wrong radii: on the target, parameters crowded around the tube.
  SurfaceFitOptions options;
  options.maxIterations = 3;
  options.reparametrize = false;
  const BSplineSurface crowded =
      fitSurface(torusSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.7, 0.8, layout),
                 torus, options)
          .surface;
  const detail::Reparametrization spread = detail::chordLengthReparametrized(crowded);
  const detail::Reparametrization again = detail::chordLengthReparametrized(spread.surface);
  const double before = largestDistance(crowded, torus);
  const double after = largestDistance(spread.surface, torus);
  std::printf("crowded torus: shift %.3g, after %.3g; max distance %.3g -> %.3g\n", spread.shift,
              again.shift, before, after);
  EXPECT_GT(spread.shift, 0.02);
  EXPECT_LT(again.shift, 0.1 * spread.shift);
  // The same shape (to the spline space's approximation error), closer to the circle fits.
  EXPECT_LT(after, before);
  EXPECT_LT(after, 2.0 * largestDistance(even, torus));
}

}  // namespace
}  // namespace d2vdb
