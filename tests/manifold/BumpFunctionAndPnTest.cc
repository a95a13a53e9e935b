// The chart weights' cut-off function (exact values, derivatives, flat ends) and PN triangles.
#include <gtest/gtest.h>

#include <cmath>

#include "ManifoldTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/BumpFunction.h"
#include "d2vdb/manifold/PnTriangles.h"
#include "d2vdb/manifold/PseudoManifold.h"
#include "d2vdb/manifold/SourceDistance.h"

namespace d2vdb {
namespace {

using Index = HalfEdgeMesh::Index;

TEST(ChartBump, ExactValuesAtTheEndsAndTheMidpoint) {
  EXPECT_EQ(chartBump(0.0).value, 1.0);
  EXPECT_EQ(chartBump(0.25).value, 1.0);
  EXPECT_EQ(chartBump(0.625).value, 0.5);
  EXPECT_EQ(chartBump(1.0).value, 0.0);
  EXPECT_EQ(chartBump(7.0).value, 0.0);
  EXPECT_EQ(chartBump(0.25).first, 0.0);
  EXPECT_EQ(chartBump(1.0).second, 0.0);
  // Midpoint slope: dxi/ds = -1/2, ds/dH = 8, dH/dt = 4/3.
  EXPECT_NEAR(chartBump(0.625).first, -0.5 * 8.0 * 4.0 / 3.0, 1e-14);
  EXPECT_NEAR(chartBump(0.625).second, 0.0, 1e-12);  // odd symmetry about the midpoint
}

TEST(ChartBump, SymmetricMonotoneAndFlatAtTheEnds) {
  double previous = 1.0;
  for (int i = 1; i < 1000; ++i) {
    const double h = i / 1000.0;
    const double t = 0.25 + 0.75 * h;
    const double mirrored = 0.25 + 0.75 * (1.0 - h);
    EXPECT_NEAR(chartBump(t).value + chartBump(mirrored).value, 1.0, 1e-15);
    EXPECT_LE(chartBump(t).value, previous);
    previous = chartBump(t).value;
  }
  // Every derivative vanishes at the ends: far below any power of the distance.
  for (const double d : {1e-2, 1e-3}) {
    EXPECT_LT(std::abs(chartBump(0.25 + d).first), 1e-40);
    EXPECT_LT(std::abs(chartBump(1.0 - d).first), 1e-40);
    EXPECT_LT(std::abs(chartBump(1.0 - d).second), 1e-40);
  }
}

TEST(ChartBump, DerivativesMatchFiniteDifferences) {
  const double h = 1e-6;
  for (double t = 0.3; t < 0.96; t += 0.05) {
    const BumpValue b = chartBump(t);
    const double first = (chartBump(t + h).value - chartBump(t - h).value) / (2 * h);
    const double second = (chartBump(t + h).first - chartBump(t - h).first) / (2 * h);
    const double third = (chartBump(t + h).second - chartBump(t - h).second) / (2 * h);
    EXPECT_NEAR(b.first, first, 1e-6 * (1.0 + std::abs(first))) << t;
    EXPECT_NEAR(b.second, second, 1e-5 * (1.0 + std::abs(second))) << t;
    EXPECT_NEAR(b.third, third, 1e-5 * (1.0 + std::abs(third))) << t;
  }
  // Odd symmetry about the midpoint (xi(5/8 + u) = 1 - xi(5/8 - u)): the third derivative is
  // even, and the ends are flat to every order.
  for (const double u : {0.05, 0.2, 0.3}) {
    EXPECT_NEAR(chartBump(0.625 + u).third, chartBump(0.625 - u).third,
                1e-12 * (1.0 + std::abs(chartBump(0.625 + u).third)));
  }
  EXPECT_EQ(chartBump(0.25).third, 0.0);
  EXPECT_EQ(chartBump(1.0).third, 0.0);
  EXPECT_LT(std::abs(chartBump(1.0 - 1e-3).third), 1e-40);
}

TEST(PnTriangles, InterpolatesVerticesTangentToTheirNormals) {
  const test::DoubleMesh m = test::icosphere(1);
  const auto mesh = m.build();
  std::vector<Eigen::Vector3d> normals;
  for (const Eigen::Vector3d& p : m.positions) normals.push_back(p.normalized());
  const PnTriangles pn(mesh, normals);
  for (Index f = 0; f < mesh->faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d b = Eigen::Vector3d::Zero();
      b[k] = 1.0;
      const SourceJet jet = pn.evaluate({f, b});
      const Index v = mesh->corner(f, k);
      EXPECT_LT((jet.position - mesh->position(v)).norm(), 1e-15);
      EXPECT_NEAR(jet.d1.dot(normals[v]), 0.0, 1e-14);
      EXPECT_NEAR(jet.d2.dot(normals[v]), 0.0, 1e-14);
    }
  }
  // Continuous across edges; close to the sphere the vertices and normals come from.
  double worstRadius = 0.0;
  for (Index h = 0; h < mesh->halfEdgeCount(); ++h) {
    for (const double t : {0.2, 0.5, 0.7}) {
      FacePoint a{HalfEdgeMesh::face(h), Eigen::Vector3d::Zero()};
      a.bary[h % 3] = 1.0 - t;
      a.bary[(h + 1) % 3] = t;
      const Index twin = mesh->twin(h);
      FacePoint b{HalfEdgeMesh::face(twin), Eigen::Vector3d::Zero()};
      b.bary[twin % 3] = t;
      b.bary[(twin + 1) % 3] = 1.0 - t;
      EXPECT_LT((pn.evaluate(a).position - pn.evaluate(b).position).norm(), 1e-15);
    }
    const Eigen::Vector3d center =
        pn.evaluate({HalfEdgeMesh::face(h), Eigen::Vector3d::Constant(1.0 / 3.0)}).position;
    worstRadius = std::max(worstRadius, std::abs(center.norm() - 1.0));
  }
  // The flat triangles' centres lie 0.0625 inside; PN bulges them back to within 1 %.
  EXPECT_LT(worstRadius, 0.01);
}

TEST(PnTriangles, ComputedNormalsAndBadInput) {
  const auto mesh = test::octahedron().build();
  const PnTriangles pn(mesh);
  // Octahedron: area-weighted normals at the vertices are the vertex directions.
  for (Index v = 0; v < mesh->vertexCount(); ++v) {
    EXPECT_LT((pn.normals()[v] - mesh->position(v).normalized()).norm(), 1e-15);
  }
  EXPECT_THROW(PnTriangles(mesh, std::vector<Eigen::Vector3d>(3, Eigen::Vector3d::UnitZ())),
               InputError);
  std::vector<Eigen::Vector3d> notUnit(mesh->vertexCount(), Eigen::Vector3d(0, 0, 2));
  EXPECT_THROW(PnTriangles(mesh, notUnit), InputError);
}

TEST(PnTriangles, PseudoManifoldOverPnIsSmoothAndClose) {
  const test::DoubleMesh m = test::mixedDegreeMesh();
  const auto mesh = m.build();
  const PnTriangles pn(mesh);
  const PseudoManifold pps(pn);
  double worst = 0.0;
  for (Index h = 0; h < mesh->halfEdgeCount(); ++h) {
    FacePoint a{HalfEdgeMesh::face(h), Eigen::Vector3d::Zero()};
    a.bary[h % 3] = 0.4;
    a.bary[(h + 1) % 3] = 0.6;
    const Index twin = mesh->twin(h);
    FacePoint b{HalfEdgeMesh::face(twin), Eigen::Vector3d::Zero()};
    b.bary[twin % 3] = 0.6;
    b.bary[(twin + 1) % 3] = 0.4;
    const SmoothPoint pa = pps.evaluate(a, Derivatives::Second);
    const SmoothPoint pb = pps.evaluate(b, Derivatives::Second);
    const double scale = std::max({std::abs(pa.k1), std::abs(pa.k2), 1.0});
    worst = std::max({worst, (pa.position - pb.position).norm() / mesh->boundingBoxDiagonal(),
                      (pa.normal - pb.normal).norm() * 1e-2, std::abs(pa.k1 - pb.k1) / scale * 1e-4,
                      std::abs(pa.k2 - pb.k2) / scale * 1e-4});
  }
  // Position to 1e-12 of the diagonal, normal to 1e-10, curvatures to 1e-8 relative.
  EXPECT_LT(worst, 1e-12);
  const SourceDistanceStatistics s = distanceToSource(pps, pn, 8);
  std::printf("PPS over PN triangles, degrees 3-9: max distance %.3g, RMS %.3g of the diagonal\n",
              s.maxDistance / s.diagonal, s.rmsDistance / s.diagonal);
  EXPECT_LT(s.maxDistance / s.diagonal, 3e-3);
}

}  // namespace
}  // namespace d2vdb
