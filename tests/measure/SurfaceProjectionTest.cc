// Point-surface projection against a brute-force reference (a dense parameter grid, refined by
// Newton on the surface's own derivatives), on open sheets, a closed torus-like surface and a
// ruled (degree 1) surface; hints, threads and boundary footpoints.
#include "d2vdb/measure/SurfaceProjection.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

constexpr double kTwoPi = 6.283185307179586476925;

/// A wavy open bicubic sheet over [0, 2] x [0, 1.5]: grid control points plus random heights.
BSplineSurface wavySheet(unsigned seed, int degreeU = 3, int degreeV = 3) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> height(-0.15, 0.15);
  const int nu = 9, nv = 7;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      points.emplace_back(2.0 * i / (nu - 1), 1.5 * j / (nv - 1), height(engine));
    }
  }
  return BSplineSurface::clamped(degreeU, degreeV, nu, nv, points, {0.0, 1.0}, {-1.0, 2.0});
}

/// A closed x closed bicubic approximating the torus with radii 2 and 0.5 (control points on
/// scaled regular polygons), slightly perturbed.
BSplineSurface torusLike(unsigned seed) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  const int nu = 10, nv = 8;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < nu; ++i) {
    const double a = kTwoPi * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double b = kTwoPi * j / nv;
      const double w = 2.0 + 0.55 * std::cos(b);
      points.emplace_back(w * std::cos(a) * 1.05 + jitter(engine),
                          w * std::sin(a) * 1.05 + jitter(engine),
                          0.55 * std::sin(b) + jitter(engine));
    }
  }
  return BSplineSurface(KnotVector::periodic(3, nu, {0.0, 1.0}), KnotVector::periodic(3, nv),
                        points, true, true);
}

/// Brute force: the best of a samples x samples parameter grid, refined by a compass search (moves
/// of +-h in u, v and both, h halved when none improves, down to 1e-14 of the domain): derivative
/// free, so creases and bounds need no special care.
double referenceSquaredDistance(const BSplineSurface& surface, const Eigen::Vector3d& p,
                                int samples = 120) {
  const ParameterInterval du = surface.domainU(), dv = surface.domainV();
  double best = std::numeric_limits<double>::infinity();
  double u = du.start, v = dv.start;
  for (int i = 0; i <= samples; ++i) {
    for (int j = 0; j <= samples; ++j) {
      const double uu = du.at(static_cast<double>(i) / samples);
      const double vv = dv.at(static_cast<double>(j) / samples);
      const double d = (surface.evaluate(uu, vv) - p).squaredNorm();
      if (d < best) best = d, u = uu, v = vv;
    }
  }
  const auto value = [&](double uu, double vv) {
    if (!surface.isClosedU()) uu = std::clamp(uu, du.start, du.end);
    if (!surface.isClosedV()) vv = std::clamp(vv, dv.start, dv.end);
    return (surface.evaluate(uu, vv) - p).squaredNorm();
  };
  for (double h = 1.0 / samples; h > 1e-14;) {
    bool improved = false;
    for (const auto& [a, b] :
         {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}, std::pair{1, 1},
          std::pair{-1, -1}, std::pair{1, -1}, std::pair{-1, 1}}) {
      double uu = u + a * h * du.length(), vv = v + b * h * dv.length();
      if (!surface.isClosedU()) uu = std::clamp(uu, du.start, du.end);
      if (!surface.isClosedV()) vv = std::clamp(vv, dv.start, dv.end);
      const double d = value(uu, vv);
      if (d < best) {
        best = d, u = uu, v = vv, improved = true;
        break;
      }
    }
    if (!improved) h *= 0.5;
  }
  return best;
}

void expectMatchesBruteForce(const BSplineSurface& surface,
                             const std::vector<Eigen::Vector3d>& queries) {
  const SurfaceProjector projector(surface);
  for (const Eigen::Vector3d& p : queries) {
    const SurfaceFootpoint found = projector.nearest(p);
    const double reference = referenceSquaredDistance(surface, p);
    ASSERT_GE(found.patch, 0);
    // Never farther than the reference (to rounding), and never nearer than the true surface.
    EXPECT_LE(std::sqrt(found.squaredDistance), std::sqrt(reference) + 1e-12) << p.transpose();
    EXPECT_GE(std::sqrt(found.squaredDistance), std::sqrt(reference) - 1e-9) << p.transpose();
    EXPECT_LT((surface.evaluate(found.u, found.v) - found.point).norm(), 1e-13);
    const BezierPatch& patch = projector.patches()[static_cast<std::size_t>(found.patch)];
    const bool insidePatch = found.u > patch.intervalU.start && found.u < patch.intervalU.end &&
                             found.v > patch.intervalV.start && found.v < patch.intervalV.end;
    if (insidePatch) {  // orthogonality at a footpoint inside a polynomial piece
      const SurfaceDerivatives d = surface.derivatives(found.u, found.v);
      const Eigen::Vector3d r = found.point - p;
      EXPECT_LE(std::abs(r.dot(d.du)), 1e-11 * (1.0 + r.norm() * d.du.norm()));
      EXPECT_LE(std::abs(r.dot(d.dv)), 1e-11 * (1.0 + r.norm() * d.dv.norm()));
    }
  }
}

std::vector<Eigen::Vector3d> queriesAround(const BSplineSurface& surface, unsigned seed, int count,
                                           double spread) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), offset(-spread, spread);
  std::vector<Eigen::Vector3d> queries;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d base =
        surface.evaluate(surface.domainU().at(unit(engine)), surface.domainV().at(unit(engine)));
    queries.push_back(base + Eigen::Vector3d(offset(engine), offset(engine), offset(engine)));
  }
  return queries;
}

TEST(SurfaceProjection, OpenSheetAgreesWithBruteForce) {
  const BSplineSurface sheet = wavySheet(3);
  expectMatchesBruteForce(sheet, queriesAround(sheet, 4, 60, 0.25));
}

TEST(SurfaceProjection, ClosedTorusLikeSurfaceAgreesWithBruteForce) {
  const BSplineSurface torus = torusLike(5);
  expectMatchesBruteForce(torus, queriesAround(torus, 6, 60, 0.2));
}

TEST(SurfaceProjection, RuledSurfaceAgreesWithBruteForce) {
  // Degree (1, 3): straight rulings between two cubic boundary curves, plus a piecewise ruled one.
  const BSplineSurface ruled = wavySheet(7, 1, 3);
  expectMatchesBruteForce(ruled, queriesAround(ruled, 8, 40, 0.25));
}

TEST(SurfaceProjection, PointsBeyondAnOpenEdgeProjectOntoTheBoundary) {
  const BSplineSurface sheet = wavySheet(9);
  const SurfaceProjector projector(sheet);
  // Far beyond the u = end edge (x = 2), and beyond a corner.
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(3.0, 0.7, 0.1), Eigen::Vector3d(-1, -1, 0.3)}) {
    const SurfaceFootpoint found = projector.nearest(p);
    EXPECT_TRUE(found.onBoundary);
    EXPECT_NEAR(std::sqrt(found.squaredDistance), std::sqrt(referenceSquaredDistance(sheet, p)),
                1e-12);
  }
  const SurfaceFootpoint inside =
      projector.nearest(sheet.evaluate(0.4, 0.5) + Eigen::Vector3d(0, 0, 0.01));
  EXPECT_FALSE(inside.onBoundary);
}

TEST(SurfaceProjection, HintsAndThreadCountsGiveTheSameFootpoints) {
  const BSplineSurface torus = torusLike(10);
  const std::vector<Eigen::Vector3d> queries = queriesAround(torus, 11, 3000, 0.1);
  const SurfaceProjector projector(torus);
  std::vector<SurfaceFootpoint> one, two;
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = projector.nearest(queries);
  }
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = projector.nearest(queries);
  }
  // A slightly moved surface with the same knots, projected with the old footpoints as hints.
  std::vector<Eigen::Vector3d> moved = torus.controlPoints();
  for (Eigen::Vector3d& point : moved) point *= 1.001;
  BSplineSurface next = torus;
  next.setControlPoints(moved);
  const SurfaceProjector nextProjector(next);
  const std::vector<SurfaceFootpoint> hinted = nextProjector.nearest(queries, one);
  const std::vector<SurfaceFootpoint> unhinted = nextProjector.nearest(queries);
  for (std::size_t i = 0; i < queries.size(); ++i) {
    EXPECT_EQ(one[i].u, two[i].u);
    EXPECT_EQ(one[i].v, two[i].v);
    EXPECT_EQ(one[i].squaredDistance, two[i].squaredDistance);
    EXPECT_NEAR(std::sqrt(hinted[i].squaredDistance), std::sqrt(unhinted[i].squaredDistance),
                1e-12);
  }
}

TEST(SurfaceProjection, NonFiniteQueriesAreRejected) {
  const SurfaceProjector projector(wavySheet(1));
  EXPECT_THROW(projector.nearest(Eigen::Vector3d(std::nan(""), 0, 0)), InputError);
  EXPECT_THROW(projector.nearest(std::vector<Eigen::Vector3d>{Eigen::Vector3d::Zero()},
                                 std::vector<SurfaceFootpoint>(2)),
               InputError);
}

}  // namespace
}  // namespace d2vdb
