// The smooth-surface target: exact projection onto a pseudo-manifold built from a fine mesh of a
// sphere, against the sphere (footpoints, normals, curvatures, signed distances), and its
// agreement with brute force, determinism and domain.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/SmoothSurface.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/PnTriangles.h"
#include "d2vdb/manifold/SourceDistance.h"
#include "manifold/ManifoldTestSupport.h"

namespace d2vdb {
namespace {

/// Random points at distance -0.3 .. 0.3 from the unit sphere.
std::vector<Eigen::Vector3d> shellPoints(int count) {
  std::mt19937 random(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> offset(-0.3, 0.3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d direction =
        Eigen::Vector3d(normal(random), normal(random), normal(random)).normalized();
    points.push_back((1.0 + offset(random)) * direction);
  }
  return points;
}

struct SphereErrors {
  double radius = 0.0;    ///< max | |s| - 1 |
  double normal = 0.0;    ///< max angle between n and s / |s|
  double distance = 0.0;  ///< max |d - (|x| - 1)|
};

SphereErrors sphereErrors(const SmoothSurface& target, const std::vector<Eigen::Vector3d>& points) {
  SphereErrors e;
  for (const Approximant& a : target.approximantsAt(points)) {
    e.radius = std::max(e.radius, std::abs(a.footpoint.norm() - 1.0));
    e.normal = std::max(e.normal, std::acos(std::min(1.0, a.normal.dot(a.footpoint.normalized()))));
    e.distance = std::max(e.distance, std::abs(a.distance - (a.origin.norm() - 1.0)));
    EXPECT_EQ(a.flags, 0);
    EXPECT_LT((a.origin - a.footpoint - a.distance * a.normal).norm(), 1e-10);
  }
  return e;
}

TEST(SmoothSurface, FootpointsAndNormalsOfAFineSphere) {
  // PN triangles over an icosphere with the sphere's own normals, then the smooth surface.
  // (Curvatures are checked on the torus below: neither source has a sphere's constant
  // curvature on an icosphere — the Loop limit surface ripples by about 12 %, PN patches meet
  // with kinks.)
  const test::DoubleMesh m = test::icosphere(4);
  const auto mesh = m.build();
  std::vector<Eigen::Vector3d> normals;
  for (const Eigen::Vector3d& p : m.positions) normals.push_back(p.normalized());
  const PnTriangles pn(mesh, normals);
  const SmoothSurface target(std::make_shared<const PseudoManifold>(pn));
  const SphereErrors e = sphereErrors(target, shellPoints(2000));
  std::printf("sphere (icosphere 4, PN): footpoint radius %.3g, normal %.3g rad, distance %.3g\n",
              e.radius, e.normal, e.distance);
  EXPECT_LT(e.radius, 2e-5);
  EXPECT_LT(e.normal, 1.5e-3);
  EXPECT_LT(e.distance, 2e-5);
}

struct TorusErrors {
  double footpoint = 0.0;  ///< max |s - s_exact| / r
  double normal = 0.0;     ///< max angle (rad)
  double curvature = 0.0;  ///< max |k_i - k_i exact| r
  double direction = 0.0;  ///< max angle between e1 and the exact e1 (degrees)
};

TorusErrors torusErrors(int around, int across) {
  const double major = 3.0;
  const double minor = 1.0;
  const auto mesh = test::torus(major, minor, around, across).build();
  const LoopLimitSurface loop(mesh);
  const SmoothSurface target(std::make_shared<const PseudoManifold>(loop));
  const Torus torus(Eigen::Vector3d::Zero(), major, minor);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  std::uniform_real_distribution<double> offset(-0.3, 0.3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 1000; ++i) {
    const double u = angle(random);
    const double v = angle(random);
    const double s = minor + offset(random);
    points.emplace_back((major + s * std::cos(v)) * std::cos(u),
                        (major + s * std::cos(v)) * std::sin(u), s * std::sin(v));
  }
  TorusErrors e;
  for (const Approximant& a : target.approximantsAt(points)) {
    const SurfacePoint exact = torus.closestSurfacePoint(a.origin);
    e.footpoint = std::max(e.footpoint, (a.footpoint - exact.point).norm() / minor);
    e.normal = std::max(e.normal, std::acos(std::min(1.0, a.normal.dot(exact.normal))));
    e.curvature = std::max(
        {e.curvature, std::abs(a.k1 - exact.k1) * minor, std::abs(a.k2 - exact.k2) * minor});
    e.direction = std::max(e.direction,
                           std::acos(std::min(1.0, std::abs(a.tangent.dot(exact.e1)))) * 180 / kPi);
  }
  std::printf("torus %d x %d: footpoint %.3g r, normal %.3g rad, curvature %.3g / r, e1 %.3g deg\n",
              around, across, e.footpoint, e.normal, e.curvature, e.direction);
  return e;
}

TEST(SmoothSurface, CurvaturesOfATorusConvergeWithTheMesh) {
  // Every vertex of degree 6: the Loop limit surface of the sampled torus is within O(h^2) of
  // the torus, and the smooth surface follows it, curvatures and principal directions included.
  const TorusErrors coarse = torusErrors(48, 16);
  const TorusErrors fine = torusErrors(96, 32);
  EXPECT_LT(fine.footpoint, 0.0125);
  EXPECT_LT(fine.normal, 0.005);
  EXPECT_LT(fine.curvature, 0.0125);
  EXPECT_LT(fine.direction, 0.3);
  // Second order: halving the edges divides the errors by about 4.
  EXPECT_GT(coarse.footpoint / fine.footpoint, 3.5);
  EXPECT_GT(coarse.curvature / fine.curvature, 3.5);
}

TEST(SmoothSurface, ProjectionIsTheNearestPoint) {
  const test::DoubleMesh m = test::mixedDegreeMesh();
  const auto mesh = m.build();
  const LoopLimitSurface loop(mesh);
  const auto surface = std::make_shared<const PseudoManifold>(loop);
  const SmoothSurface target(surface);
  // Brute force: the nearest of dense samples, then the surface can only be closer.
  std::vector<Eigen::Vector3d> dense;
  for (HalfEdgeMesh::Index f = 0; f < mesh->faceCount(); ++f) {
    for (const Eigen::Vector3d& b : faceLattice(20)) dense.push_back(surface->position({f, b}));
  }
  for (const Eigen::Vector3d& x : shellPoints(200)) {
    double best = 1e300;
    for (const Eigen::Vector3d& p : dense) best = std::min(best, (p - x).norm());
    const Approximant a = target.approximantAt(x);
    EXPECT_LE(std::abs(a.distance), best + 1e-12);
    // The residual is along the normal at the footpoint.
    EXPECT_LT((x - a.footpoint).cross(a.normal).norm(), 1e-10);
  }
}

TEST(SmoothSurface, SameAnswersForAnyThreadCountAndDomainChecked) {
  const auto mesh = test::icosphere(2).build();
  const LoopLimitSurface loop(mesh);
  const SmoothSurface target(std::make_shared<const PseudoManifold>(loop));
  const std::vector<Eigen::Vector3d> points = shellPoints(300);
  const auto one = test::withThreads(1, [&] { return target.approximantsAt(points); });
  const auto two = test::withThreads(2, [&] { return target.approximantsAt(points); });
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(one[i].footpoint, two[i].footpoint);
    EXPECT_EQ(one[i].k1, two[i].k1);
  }
  EXPECT_THROW(target.approximantAt(Eigen::Vector3d(9.0, 0.0, 0.0)), InputError);
  EXPECT_THROW(target.approximantAt(Eigen::Vector3d(NAN, 0.0, 0.0)), InputError);
  EXPECT_NE(target.describe().find("smooth surface (loop) of 320 faces"), std::string::npos);
  EXPECT_THROW(SmoothSurface(nullptr), InputError);
}

}  // namespace
}  // namespace d2vdb
