// fitSupportOverDomain() and checkSupportFunction(): the fit of the domain's default weight, the
// validity of an ellipsoid's fit against its exact support function h(n) = |A n| and principal
// radii, and the refusals (singular, missing its samples) with what they say.
#include "d2vdb/support/SupportCheck.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "common/ExpectInputError.h"
#include "support/SupportTestSupport.h"

namespace d2vdb {
namespace {

using Eigen::Vector3d;

// A sphere of radius 1 whose sample points are moved alternately 0.1 out and in along their
// normals: any support function misses them by about 0.1, over 2.5% of their bounding box's
// diagonal.
OrientedSamples roughSphere() {
  OrientedSamples samples;
  samples.normals = test::randomUnitVectors(400, 3);
  for (std::size_t i = 0; i < samples.normals.size(); ++i) {
    samples.points.push_back((i % 2 == 0 ? 1.1 : 0.9) * samples.normals[i]);
  }
  return samples;
}

// h = Y_0^0 + 5 Y_2^0: the sum of the principal radii, Delta_S h + 2 h, changes sign on the
// sphere (a degree-2 harmonic contributes -4 times itself), so x_h has cusps.
SupportFunction singularFunction() {
  Eigen::VectorXd coefficients = Eigen::VectorXd::Zero(harmonicCount(2));
  coefficients[harmonicIndex(0, 0)] = 1.0;
  coefficients[harmonicIndex(2, 0)] = 5.0;
  return SupportFunction(2, coefficients);
}

TEST(SupportCheck, ValidityDomainIsThePatchOrTheValidationSphere) {
  const SupportFunction h = singularFunction();
  const SphericalTriangulation sphere = validityDomain(h, std::nullopt);
  EXPECT_EQ(sphere.normals.size(), validationSphere(2).normals.size());
  EXPECT_EQ(sphere.triangles, validationSphere(2).triangles);
  SphericalTriangulation patch;
  patch.normals = {Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()};
  patch.triangles = {{0, 1, 2}};
  const SphericalTriangulation domain = validityDomain(h, patch);
  EXPECT_EQ(domain.normals, patch.normals);
  EXPECT_EQ(domain.triangles, patch.triangles);
}

TEST(SupportCheck, FitOverADomainTakesItsDefaultWeightAndMatchesTheEllipsoid) {
  const test::Ellipsoid ellipsoid;
  const OrientedSamples samples = ellipsoid.samples(3000, 11);
  const DomainSupportFit sphere = fitSupportOverDomain(samples, false, 12, -1.0, "'e'");
  EXPECT_EQ(sphere.report.regularization, kDefaultSupportRegularization);
  EXPECT_TRUE(sphere.warnings.empty());
  EXPECT_EQ(fitSupportOverDomain(samples, true, 12, -1.0, "'e'").report.regularization,
            kPatchSupportRegularization);
  EXPECT_EQ(fitSupportOverDomain(samples, true, 12, 1e-8, "'e'").report.regularization, 1e-8);
  // The fit against the exact support function at normals it was not fitted to.
  double worst = 0.0;
  for (const Vector3d& n : test::randomUnitVectors(2000, 12)) {
    worst = std::max(worst, std::abs(sphere.function.evaluate(n).value - ellipsoid.support(n)));
  }
  EXPECT_LT(worst, 1e-3);

  // Normals of length 1.5 are normalised, with a warning that says how many.
  OrientedSamples longNormals = samples;
  for (Vector3d& n : longNormals.normals) n *= 1.5;
  const DomainSupportFit normalized = fitSupportOverDomain(longNormals, false, 12, -1.0, "'e'");
  ASSERT_EQ(normalized.warnings.size(), 1u);
  EXPECT_NE(normalized.warnings[0].find("3000 sample normals were not unit length (off by up to "
                                        "0.5)"),
            std::string::npos)
      << normalized.warnings[0];
}

TEST(SupportCheck, AcceptsTheEllipsoidWithItsRadiiAndSafeOffsets) {
  const test::Ellipsoid ellipsoid;  // semi-axes 2, 1.5, 1
  const DomainSupportFit fit =
      fitSupportOverDomain(ellipsoid.samples(6000, 13), false, 16, -1.0, "'e'");
  const SupportCheck check =
      checkSupportFunction(fit.function, std::nullopt, fit.report, std::nullopt, "'e'", false);
  EXPECT_TRUE(check.warnings.empty());
  ASSERT_TRUE(check.validity.regular());
  EXPECT_EQ(check.validity.signs, RadiusSigns::Convex);
  // Principal radii of the ellipsoid: c^2 / a = 0.5 at the ends of the long axis, a^2 / c = 4 at
  // those of the short one.
  EXPECT_NEAR(check.validity.minRadius, 0.5, 1e-3);
  EXPECT_NEAR(check.validity.maxRadius, 4.0, 1e-2);
  EXPECT_NEAR(check.validity.safeOffsetMin, -0.5, 1e-3);
  EXPECT_EQ(check.validity.safeOffsetMax, std::numeric_limits<double>::infinity());
}

TEST(SupportCheck, RefusesASingularFunctionOrWarnsWhenAllowed) {
  const SupportFunction h = singularFunction();
  test::expectInputError(
      [&] { checkSupportFunction(h, std::nullopt, std::nullopt, std::nullopt, "'s.json'", false); },
      {"'s.json': the support function is singular",
       "A closed surface has a support function only if it is convex", "pass --patches",
       "--method levelset", ", or pass --allow-singular to keep this result"});
  const SupportCheck kept =
      checkSupportFunction(h, std::nullopt, std::nullopt, std::nullopt, "'s.json'", true);
  EXPECT_FALSE(kept.validity.regular());
  ASSERT_EQ(kept.warnings.size(), 1u);
  EXPECT_NE(kept.warnings[0].find("(kept: --allow-singular)"), std::string::npos);

  // A mesh whose triangles keep and reverse their orientation on the sphere: the message says so.
  MeshGaussImage image;
  image.preservingTriangles = 30;
  image.reversingTriangles = 20;
  image.collapsedTriangles = 2;
  test::expectInputError(
      [&] { checkSupportFunction(h, std::nullopt, std::nullopt, image, "'m.obj'", false); },
      {"Of its 52 triangles, 20 have a saddle-shaped (orientation-reversing) Gauss image and 30 a "
       "convex one, so its Gauss map is not injective."});
  // Over a patch the explanation is the patch's.
  SphericalTriangulation patch;
  patch.normals = {Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()};
  patch.triangles = {{0, 1, 2}};
  test::expectInputError(
      [&] { checkSupportFunction(h, patch, std::nullopt, std::nullopt, "'p'", false); },
      {"A patch has a support function only where its Gauss map is injective"});
}

TEST(SupportCheck, RefusesARegularFitThatMissesItsSamples) {
  const DomainSupportFit fit = fitSupportOverDomain(roughSphere(), false, 2, -1.0, "'rough'");
  const double relative = fit.report.maxResidual / fit.report.size;
  ASSERT_GT(relative, kMaxRelativeSupportResidual);
  test::expectInputError(
      [&] {
        checkSupportFunction(fit.function, std::nullopt, fit.report, std::nullopt, "'rough'",
                             false);
      },
      {"'rough': the support function is regular", "but misses the samples by up to",
       "% of the size, more than 2%"});
  const SupportCheck kept =
      checkSupportFunction(fit.function, std::nullopt, fit.report, std::nullopt, "'rough'", true);
  EXPECT_TRUE(kept.validity.regular());
  EXPECT_EQ(kept.warnings.size(), 1u);
  // Without its fit report (a function read from a file) the residual is not judged.
  EXPECT_TRUE(
      checkSupportFunction(fit.function, std::nullopt, std::nullopt, std::nullopt, "'r'", false)
          .warnings.empty());
}

}  // namespace
}  // namespace d2vdb
