#include "d2vdb/support/SupportMeasures.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

#include "SupportTestSupport.h"
#include "d2vdb/support/SphereQuadrature.h"
#include "d2vdb/support/SupportFit.h"
#include "d2vdb/support/SupportTessellation.h"

namespace d2vdb {
namespace {

// Surface area of the ellipsoid from its parametrisation (a sin t cos p, b sin t sin p, c cos t),
// Gauss-Legendre in cos t times the trapezoidal rule in p: an independent reference.
double ellipsoidArea(const test::Ellipsoid& e) {
  const SphereQuadrature rule = sphereQuadrature(300);
  double area = 0.0;
  for (std::size_t q = 0; q < rule.nodes.size(); ++q) {
    const Eigen::Vector3d& n = rule.nodes[q];
    // Area element of the map n -> (a x, b y, c z) from the sphere: |cofactor(A) n|.
    const Eigen::Vector3d cofactor(e.b * e.c * n.x(), e.a * e.c * n.y(), e.a * e.b * n.z());
    area += rule.weights[q] * cofactor.norm();
  }
  return area;
}

TEST(SupportMeasures, SphereHasTheClosedForms) {
  const SupportFunction h = SupportFunction::sphere(Eigen::Vector3d(1, 2, 3), 0.7, 4);
  const SupportMeasures m = supportMeasures(h);
  EXPECT_NEAR(m.area, 4 * kPi * 0.49, 1e-12);
  EXPECT_NEAR(m.volume, 4.0 / 3.0 * kPi * 0.343, 1e-12);
  EXPECT_NEAR(m.meanCurvatureIntegral, 4 * kPi * 0.7, 1e-12);
}

// Steiner's formula V(d) = V + A d + M d^2 + (4 pi / 3) d^3 for the offsets of the fitted
// ellipsoid: the volumes computed directly for h + d agree with the polynomial of h, and both with
// the exact ellipsoid's polynomial to the accuracy of the fit.
TEST(SupportMeasures, SteinerFormulaHoldsForTheFittedEllipsoid) {
  const test::Ellipsoid ellipsoid;
  const SupportFunction h = fitSupportFunction(ellipsoid.samples(5000, 91), {20});
  const SupportMeasures m = supportMeasures(h);
  const double exactVolume = 4.0 / 3.0 * kPi * ellipsoid.a * ellipsoid.b * ellipsoid.c;
  const double exactArea = ellipsoidArea(ellipsoid);
  const SphereQuadrature rule = sphereQuadrature(200);
  double exactMean = 0.0;
  for (std::size_t q = 0; q < rule.nodes.size(); ++q) {
    exactMean += rule.weights[q] * ellipsoid.support(rule.nodes[q]);
  }
  // Fit error at L = 20 is about 2e-6 a; area and volume follow to that order.
  EXPECT_NEAR(m.volume, exactVolume, 1e-4);
  EXPECT_NEAR(m.area, exactArea, 1e-4);
  EXPECT_NEAR(m.meanCurvatureIntegral, exactMean, 1e-5);
  for (const double d : {-0.3, 0.25, 1.0}) {
    const double direct = supportMeasures(h.offset(d)).volume;
    EXPECT_NEAR(direct, m.offsetVolume(d), 1e-11 * std::abs(direct));
    const double exact =
        exactVolume + exactArea * d + exactMean * d * d + 4.0 / 3.0 * kPi * d * d * d;
    EXPECT_NEAR(direct, exact, 2e-4) << "d = " << d;
  }
}

TEST(SupportTessellation, ClosedOutwardMeshOfTheOffsetSurface) {
  const test::Ellipsoid ellipsoid;
  const SupportFunction h = fitSupportFunction(ellipsoid.samples(2000, 5), {12});
  const SphericalTriangulation sphere = geodesicSphere(5);
  const double d = 0.25;
  const TriangleMesh mesh = tessellateSupport(h, sphere, d);
  ASSERT_EQ(mesh.positions.size(), sphere.normals.size());
  const test::ClosedMeshCheck check = test::checkClosedMesh(mesh);
  EXPECT_TRUE(check.closedAndOriented);
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d a = mesh.positions[tri[0]].cast<double>();
    const Eigen::Vector3d b = mesh.positions[tri[1]].cast<double>();
    const Eigen::Vector3d c = mesh.positions[tri[2]].cast<double>();
    EXPECT_GT((b - a).cross(c - a).dot(mesh.normals[tri[0]].cast<double>()), 0.0);
  }
  for (std::size_t i = 0; i < sphere.normals.size(); i += 37) {
    EXPECT_LT((mesh.positions[i].cast<double>() - h.point(sphere.normals[i], d)).norm(), 1e-6);
    EXPECT_LT((mesh.normals[i].cast<double>() - sphere.normals[i]).norm(), 1e-6);
  }
  // The inscribed mesh's volume approaches Steiner's value from below (chords, O(h^2)).
  const double steiner = supportMeasures(h).offsetVolume(d);
  EXPECT_LT(check.volume, steiner);
  EXPECT_GT(check.volume, steiner * (1.0 - 1.5e-3));
}

}  // namespace
}  // namespace d2vdb
