#include "d2vdb/spline/BSplineSurface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/spline/BasisFunctions.h"
#include "spline/SplineTestSupport.h"

namespace {

using d2vdb::BSplineSurface;
using d2vdb::InputError;
using d2vdb::KnotVector;
using Eigen::Vector3d;

BSplineSurface randomSurface(std::mt19937& rng, int degreeU, int degreeV, bool clamped) {
  KnotVector knotsU = d2vdb::test::randomKnotVector(rng, degreeU, clamped);
  KnotVector knotsV = d2vdb::test::randomKnotVector(rng, degreeV, !clamped);
  const int count = knotsU.basisFunctionCount() * knotsV.basisFunctionCount();
  return BSplineSurface(std::move(knotsU), std::move(knotsV),
                        d2vdb::test::randomPoints(rng, count));
}

// The blossom values e_k(t_{i+1..i+p}) / C(p, k) of every control point index i.
std::vector<std::vector<double>> monomialBlossoms(const KnotVector& knots) {
  std::vector<std::vector<double>> result;
  for (int i = 0; i < knots.basisFunctionCount(); ++i) {
    std::vector<double> arguments;
    for (int r = 1; r <= knots.degree(); ++r) arguments.push_back(knots[i + r]);
    std::vector<double> values;
    for (int k = 0; k <= knots.degree(); ++k) {
      values.push_back(d2vdb::test::monomialBlossom(arguments, k));
    }
    result.push_back(values);
  }
  return result;
}

double power(double x, int k) {
  return k < 0 ? 0.0 : std::pow(x, k);
}

TEST(BSplineSurface, ReproducesATensorPolynomialAndItsDerivatives) {
  std::mt19937 rng(51);
  for (int trial = 0; trial < 20; ++trial) {
    const int p = 1 + trial % 4;
    const int q = 1 + (trial / 2) % 4;
    const KnotVector knotsU = d2vdb::test::randomKnotVector(rng, p, trial % 2 == 0);
    const KnotVector knotsV = d2vdb::test::randomKnotVector(rng, q, trial % 3 == 0);
    // f(u, v) = sum a_kl u^k v^l with random vector coefficients a_kl (k <= p, l <= q).
    const std::vector<Vector3d> a = d2vdb::test::randomPoints(rng, (p + 1) * (q + 1));
    auto coefficient = [&](int k, int l) { return a[static_cast<std::size_t>(k * (q + 1) + l)]; };
    const auto blossomU = monomialBlossoms(knotsU);
    const auto blossomV = monomialBlossoms(knotsV);
    std::vector<Vector3d> points;
    for (int i = 0; i < knotsU.basisFunctionCount(); ++i) {
      for (int j = 0; j < knotsV.basisFunctionCount(); ++j) {
        Vector3d point = Vector3d::Zero();
        for (int k = 0; k <= p; ++k) {
          for (int l = 0; l <= q; ++l) {
            point += coefficient(k, l) *
                     blossomU[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] *
                     blossomV[static_cast<std::size_t>(j)][static_cast<std::size_t>(l)];
          }
        }
        points.push_back(point);
      }
    }
    const BSplineSurface surface(knotsU, knotsV, points);
    EXPECT_EQ(surface.countU(), knotsU.basisFunctionCount());
    EXPECT_EQ(surface.countV(), knotsV.basisFunctionCount());
    for (int sample = 0; sample < 60; ++sample) {
      const double u = sample == 0 ? surface.domainU().end
                                   : d2vdb::test::randomParameter(rng, surface.domainU().start,
                                                                  surface.domainU().end);
      const double v = sample == 0 ? surface.domainV().start
                                   : d2vdb::test::randomParameter(rng, surface.domainV().start,
                                                                  surface.domainV().end);
      // Analytic partial derivatives of the polynomial.
      Vector3d f = Vector3d::Zero(), fu = f, fv = f, fuu = f, fuv = f, fvv = f;
      for (int k = 0; k <= p; ++k) {
        for (int l = 0; l <= q; ++l) {
          const Vector3d c = coefficient(k, l);
          f += c * power(u, k) * power(v, l);
          fu += c * k * power(u, k - 1) * power(v, l);
          fv += c * l * power(u, k) * power(v, l - 1);
          fuu += c * k * (k - 1) * power(u, k - 2) * power(v, l);
          fuv += c * k * l * power(u, k - 1) * power(v, l - 1);
          fvv += c * l * (l - 1) * power(u, k) * power(v, l - 2);
        }
      }
      const d2vdb::SurfaceDerivatives d = surface.derivatives(u, v);
      EXPECT_LT((surface.evaluate(u, v) - f).norm(), 1e-11);
      EXPECT_LT((d.point - f).norm(), 1e-11);
      EXPECT_LT((d.du - fu).norm(), 1e-10);
      EXPECT_LT((d.dv - fv).norm(), 1e-10);
      EXPECT_LT((d.duu - fuu).norm(), 1e-9);
      EXPECT_LT((d.duv - fuv).norm(), 1e-9);
      EXPECT_LT((d.dvv - fvv).norm(), 1e-9);
    }
  }
}

TEST(BSplineSurface, PartialDerivativesMatchCentralDifferences) {
  std::mt19937 rng(52);
  const double h = 1e-6;
  for (int trial = 0; trial < 20; ++trial) {
    const BSplineSurface surface = randomSurface(rng, 2 + trial % 3, 3 + trial % 2, trial % 2 == 0);
    int checked = 0;
    while (checked < 10) {
      const double u =
          d2vdb::test::randomParameter(rng, surface.domainU().start + h, surface.domainU().end - h);
      const double v =
          d2vdb::test::randomParameter(rng, surface.domainV().start + h, surface.domainV().end - h);
      bool nearKnot = false;
      for (double knot : surface.knotsU().values())
        nearKnot = nearKnot || std::abs(u - knot) < 2 * h;
      for (double knot : surface.knotsV().values())
        nearKnot = nearKnot || std::abs(v - knot) < 2 * h;
      if (nearKnot) continue;
      ++checked;
      const d2vdb::SurfaceDerivatives d = surface.derivatives(u, v);
      const d2vdb::SurfaceDerivatives up = surface.derivatives(u + h, v);
      const d2vdb::SurfaceDerivatives um = surface.derivatives(u - h, v);
      const d2vdb::SurfaceDerivatives vp = surface.derivatives(u, v + h);
      const d2vdb::SurfaceDerivatives vm = surface.derivatives(u, v - h);
      auto expectClose = [](const Vector3d& exact, const Vector3d& difference) {
        EXPECT_LT((exact - difference).norm(), 1e-5 * (1.0 + exact.norm()));
      };
      expectClose(d.du, (up.point - um.point) / (2 * h));
      expectClose(d.dv, (vp.point - vm.point) / (2 * h));
      expectClose(d.duu, (up.du - um.du) / (2 * h));
      expectClose(d.duv, (vp.du - vm.du) / (2 * h));
      expectClose(d.duv, (up.dv - um.dv) / (2 * h));
      expectClose(d.dvv, (vp.dv - vm.dv) / (2 * h));
    }
  }
}

TEST(BSplineSurface, ClosedDirectionsArePeriodicAndSmoothAcrossTheSeams) {
  std::mt19937 rng(53);
  const int p = 3;
  const int q = 2;
  const int nu = 6;
  const int nv = 4;
  const std::vector<Vector3d> unique = d2vdb::test::randomPoints(rng, nu * nv);
  const BSplineSurface closed(KnotVector::periodic(p, nu), KnotVector::periodic(q, nv, {0.0, 2.0}),
                              unique, true, true);
  EXPECT_TRUE(closed.isClosedU());
  EXPECT_TRUE(closed.isClosedV());
  EXPECT_EQ(closed.countU(), nu);
  EXPECT_EQ(closed.countV(), nv);
  // An independent open surface on the same knots with the control grid wrapped by hand.
  std::vector<Vector3d> wrapped;
  for (int i = 0; i < nu + p; ++i) {
    for (int j = 0; j < nv + q; ++j) {
      wrapped.push_back(unique[static_cast<std::size_t>((i % nu) * nv + j % nv)]);
    }
  }
  const BSplineSurface open(closed.knotsU(), closed.knotsV(), wrapped);
  for (int k = 0; k < 40; ++k) {
    const double u = d2vdb::test::randomParameter(rng, 0.0, 1.0);
    const double v = d2vdb::test::randomParameter(rng, 0.0, 2.0);
    EXPECT_LT((closed.evaluate(u, v) - open.evaluate(u, v)).norm(), 1e-13);
    EXPECT_LT((closed.evaluate(u + 1.0, v - 2.0) - closed.evaluate(u, v)).norm(), 1e-12);
    // Across the u seam (C^2 for p = 3): the open surface's last piece at u = 1 against the
    // closed surface at u = 0.
    const d2vdb::SurfaceDerivatives end = open.derivatives(1.0, v);
    const d2vdb::SurfaceDerivatives start = closed.derivatives(0.0, v);
    EXPECT_LT((end.point - start.point).norm(), 1e-12);
    EXPECT_LT((end.du - start.du).norm(), 1e-10);
    EXPECT_LT((end.duu - start.duu).norm(), 1e-9);
    EXPECT_LT((end.dv - start.dv).norm(), 1e-10);
    // Across the v seam (C^1 for q = 2).
    const d2vdb::SurfaceDerivatives endV = open.derivatives(u, 2.0);
    const d2vdb::SurfaceDerivatives startV = closed.derivatives(u, 0.0);
    EXPECT_LT((endV.point - startV.point).norm(), 1e-12);
    EXPECT_LT((endV.dv - startV.dv).norm(), 1e-10);
    EXPECT_LT((endV.du - startV.du).norm(), 1e-10);
  }
}

TEST(BSplineSurface, SampleGridLayoutAndBasisIndexing) {
  std::mt19937 rng(54);
  const BSplineSurface surface = BSplineSurface::clamped(
      2, 3, 4, 5, d2vdb::test::randomPoints(rng, 20), {0.0, 1.0}, {-1.0, 1.0});
  EXPECT_EQ(surface.controlPoint(2, 3), surface.controlPoints()[2 * 5 + 3]);
  const std::vector<Vector3d> grid = surface.sample(3, 4);
  ASSERT_EQ(grid.size(), 12u);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      // Same grid point up to the rounding of the parameter values.
      EXPECT_LT((grid[static_cast<std::size_t>(i * 4 + j)] -
                 surface.evaluate(i / 2.0, -1.0 + 2.0 * j / 3.0))
                    .norm(),
                1e-14);
    }
  }
  // Clamped corners interpolate the corner control points.
  EXPECT_LT((grid.front() - surface.controlPoint(0, 0)).norm(), 1e-15);
  EXPECT_LT((grid.back() - surface.controlPoint(3, 4)).norm(), 1e-14);
  // The tensor basis with controlPointIndex reproduces evaluation (what the fitters assemble).
  const double u = 0.37;
  const double v = 0.21;
  const int spanU = surface.knotsU().findSpan(u);
  const int spanV = surface.knotsV().findSpan(v);
  const d2vdb::BasisValues bu = d2vdb::basisValues(surface.knotsU(), spanU, u);
  const d2vdb::BasisValues bv = d2vdb::basisValues(surface.knotsV(), spanV, v);
  Vector3d point = Vector3d::Zero();
  for (int a = 0; a <= 2; ++a) {
    for (int b = 0; b <= 3; ++b) {
      point += bu[a] * bv[b] *
               surface.controlPoints()[static_cast<std::size_t>(
                   surface.controlPointIndex(spanU - 2 + a, spanV - 3 + b))];
    }
  }
  EXPECT_LT((point - surface.evaluate(u, v)).norm(), 1e-14);
}

TEST(BSplineSurface, ValidationRejectsBadSurfaces) {
  std::mt19937 rng(55);
  auto message = [](auto action) {
    try {
      action();
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  const std::string wrongCount = message([&] {
    BSplineSurface(KnotVector::clamped(2, 4), KnotVector::clamped(2, 3),
                   d2vdb::test::randomPoints(rng, 11));
  });
  EXPECT_NE(wrongCount.find("11 control points given"), std::string::npos) << wrongCount;
  EXPECT_NE(wrongCount.find("4 x 3 grid"), std::string::npos) << wrongCount;

  std::vector<Vector3d> points = d2vdb::test::randomPoints(rng, 12);
  points[7].y() = std::nan("");
  const std::string notFinite = message(
      [&] { BSplineSurface(KnotVector::clamped(2, 4), KnotVector::clamped(2, 3), points); });
  EXPECT_NE(notFinite.find("control point [2][1]"), std::string::npos) << notFinite;

  const std::string notPeriodic = message([&] {
    BSplineSurface(KnotVector::clamped(2, 4), KnotVector::clamped(2, 3),
                   d2vdb::test::randomPoints(rng, 12), false, true);
  });
  EXPECT_NE(notPeriodic.find("v knots of a closed direction must be uniform periodic"),
            std::string::npos)
      << notPeriodic;

  BSplineSurface surface(KnotVector::clamped(2, 4), KnotVector::clamped(2, 3),
                         d2vdb::test::randomPoints(rng, 12));
  EXPECT_THROW(surface.evaluate(1.5, 0.5), InputError);
  EXPECT_THROW(surface.derivatives(0.5, -0.5), InputError);
  EXPECT_THROW(surface.sample(1, 5), InputError);
  EXPECT_THROW(surface.setControlPoints(points), InputError);
  EXPECT_THROW(surface.setControlPoints(d2vdb::test::randomPoints(rng, 3)), InputError);
}

}  // namespace
