#include "d2vdb/support/SupportValidity.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

#include "SupportTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/support/SupportFit.h"
#include "d2vdb/support/SupportTessellation.h"

namespace d2vdb {
namespace {

TEST(SupportValidity, EllipsoidSafeRangeIsMinusTheSmallestRadius) {
  const test::Ellipsoid ellipsoid;
  const SupportFunction h = fitSupportFunction(ellipsoid.samples(3000, 41), {16});
  const SupportValidity validity = analyzeSupportValidity(h, validationSphere(16));
  ASSERT_TRUE(validity.regular()) << validity.describe();
  EXPECT_EQ(validity.signs, RadiusSigns::Convex);
  const double a = ellipsoid.a, b = ellipsoid.b, c = ellipsoid.c;
  // Smallest radius c^2 / a = 0.5 at +-e1, largest a^2 / c = 4 at +-e3 (the fit at L = 16 has
  // radii to a few 1e-4).
  EXPECT_NEAR(validity.safeOffsetMin, -c * c / a, 1e-3);
  EXPECT_NEAR(std::abs(validity.safeOffsetMinNormal.x()), 1.0, 1e-3);
  EXPECT_NEAR(validity.minRadius, c * c / a, 1e-3);
  EXPECT_NEAR(validity.maxRadius, a * a / c, 1e-2);
  EXPECT_EQ(validity.safeOffsetMax, std::numeric_limits<double>::infinity());
  EXPECT_NO_THROW(requireRegularOffset(validity, -0.3));
  EXPECT_NO_THROW(requireRegularOffset(validity, 5.0));
  EXPECT_THROW(requireRegularOffset(validity, -0.6), InputError);
  try {
    requireRegularOffset(validity, -0.6);
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("safe range"), std::string::npos) << error.what();
  }
  (void)b;
}

TEST(SupportValidity, FindsTheParabolicSetOfANonConvexFunction) {
  // h = 1 + 0.3 Y_3^0-like bump: x_h has saddle regions and parabolic curves between them.
  Eigen::VectorXd c = Eigen::VectorXd::Zero(harmonicCount(4));
  c[0] = std::sqrt(4 * kPi);
  c[harmonicIndex(4, 0)] = 0.9;
  const SupportFunction h(4, c);
  const SupportValidity validity = analyzeSupportValidity(h, validationSphere(4));
  EXPECT_FALSE(validity.regular());
  EXPECT_GT(validity.parabolicCrossings, 0u);
  EXPECT_GT(validity.saddleNormals, 0u);
  EXPECT_GT(validity.convexNormals, 0u);
  // Every located point is (nearly) on det = 0: a radius vanishes there.
  for (const Eigen::Vector3d& n : validity.parabolicPoints) {
    const SupportPoint p = h.evaluate(n);
    EXPECT_LT(std::min(std::abs(p.radius1), std::abs(p.radius2)), 1e-4);
  }
  EXPECT_THROW(requireRegularOffset(validity, 0.0), InputError);
}

// The hyperboloid of one sheet x^2 + y^2 - z^2 = 1, |z| <= 0.5, fitted over its Gauss image:
// surface and offsets d = +-0.1 within 1e-5, safe range (-1, 1) from the analytic radii
// sqrt(1 + 2 z^2) >= 1 and -(1 + 2 z^2)^(3/2) <= -1 (both extremes at the waist z = 0).
TEST(SupportValidity, HyperboloidPatchOverItsGaussImage) {
  const TriangleMesh mesh = test::hyperboloidPatch(96, 33, 0.5);
  const MeshGaussImage image = meshGaussImage(mesh, "hyperboloid");
  EXPECT_FALSE(image.closed);
  EXPECT_EQ(image.reversingTriangles, mesh.triangles.size());  // saddle everywhere
  // Exact double-precision samples on the same grid.
  OrientedSamples samples;
  for (const Eigen::Vector3f& p : mesh.positions) {
    const double theta = std::atan2(p.y(), p.x());
    const double z = p.z();
    const double rho = std::sqrt(1.0 + z * z);
    const Eigen::Vector3d x(rho * std::cos(theta), rho * std::sin(theta), z);
    samples.points.push_back(x);
    samples.normals.push_back(Eigen::Vector3d(x.x(), x.y(), -x.z()).normalized());
  }
  SupportFitReport report;
  const SupportFunction h = fitSupportFunction(samples, {20, kPatchSupportRegularization}, &report);
  // Errors at points between the samples.
  double worst = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double theta = 2.0 * kPi * (i + 0.37) / 200.0;
    for (int j = 0; j < 50; ++j) {
      const double z = -0.5 + (j + 0.5) / 50.0;
      const double rho = std::sqrt(1.0 + z * z);
      const Eigen::Vector3d x(rho * std::cos(theta), rho * std::sin(theta), z);
      const Eigen::Vector3d n = Eigen::Vector3d(x.x(), x.y(), -x.z()).normalized();
      for (const double d : {0.0, 0.1, -0.1}) {
        worst = std::max(worst, (h.point(n, d) - (x + d * n)).norm());
      }
    }
  }
  EXPECT_LT(worst, 1e-5) << "residual rms " << report.rmsResidual;
  std::printf("hyperboloid patch, L = 20: max error %.3g (surface and offsets +-0.1)\n", worst);
  const SupportValidity validity = analyzeSupportValidity(h, image.gaussImage);
  ASSERT_TRUE(validity.regular()) << validity.describe();
  EXPECT_EQ(validity.signs, RadiusSigns::Saddle);
  EXPECT_NEAR(validity.safeOffsetMin, -1.0, 1e-4);
  EXPECT_NEAR(validity.safeOffsetMax, 1.0, 1e-4);
  EXPECT_NEAR(validity.minRadius, -std::pow(1.5, 1.5), 1e-3);  // at the rims z = +-0.5
  EXPECT_NEAR(validity.maxRadius, std::sqrt(1.5), 1e-4);
  EXPECT_NO_THROW(requireRegularOffset(validity, 0.1));
  EXPECT_NO_THROW(requireRegularOffset(validity, -0.1));
  EXPECT_THROW(requireRegularOffset(validity, 1.2), InputError);
  EXPECT_THROW(requireRegularOffset(validity, -1.2), InputError);
  // The tessellated offset keeps the mesh's outward orientation on the saddle.
  const TriangleMesh offset = tessellateSupport(h, image.gaussImage, 0.1);
  for (std::size_t t = 0; t < offset.triangles.size(); t += 97) {
    const auto& tri = offset.triangles[t];
    const Eigen::Vector3f normal = (offset.positions[tri[1]] - offset.positions[tri[0]])
                                       .cross(offset.positions[tri[2]] - offset.positions[tri[0]]);
    EXPECT_GT(normal.dot(offset.normals[tri[0]]), 0.0f) << t;
  }
}

}  // namespace
}  // namespace d2vdb
