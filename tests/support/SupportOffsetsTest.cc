// The offsets of support functions and patch sets: which distances are refused (against the
// ellipsoid's exact smallest principal radius c^2 / a), the tessellation domain, and the mesh of
// the patches' offsets against the exact offset of a sphere, |x| = R + d.
#include "d2vdb/support/SupportOffsets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/ExpectInputError.h"
#include "d2vdb/support/SupportCheck.h"
#include "support/SupportTestSupport.h"

namespace d2vdb {
namespace {

using Eigen::Vector3d;

// The sphere of radius `radius` about the origin: h = radius, i.e. radius sqrt(4 pi) Y_0^0.
SupportFunction sphereFunction(double radius) {
  Eigen::VectorXd coefficients(1);
  coefficients[0] = radius * std::sqrt(4.0 * kPi);
  return SupportFunction(0, coefficients);
}

// A patch of `function` over the spherical triangle of three normals.
SupportPatch trianglePatch(const SupportFunction& function, const Vector3d& a, const Vector3d& b,
                           const Vector3d& c, double safeMin, double safeMax) {
  SupportPatch patch;
  patch.function = function;
  patch.gaussImage.gaussImage.normals = {a, b, c};
  patch.gaussImage.gaussImage.triangles = {{0, 1, 2}};
  patch.validity.safeOffsetMin = safeMin;
  patch.validity.safeOffsetMax = safeMax;
  return patch;
}

TEST(SupportOffsets, RefusesDistancesOutsideTheEllipsoidsSafeRange) {
  const test::Ellipsoid ellipsoid;  // semi-axes 2, 1.5, 1: smallest radius c^2 / a = 0.5
  const DomainSupportFit fit =
      fitSupportOverDomain(ellipsoid.samples(6000, 21), false, 16, -1.0, "'e'");
  const SupportValidity validity = analyzeSupportValidity(fit.function, validationSphere(16));
  std::vector<std::string> warnings;
  requireRegularOffsets(validity, {-0.45, 0.25, 10.0}, false, warnings);
  EXPECT_TRUE(warnings.empty());
  test::expectInputError(
      [&] {
        requireRegularOffsets(validity, {0.1, -0.55}, false, warnings);
      },
      {"offset distance -0.55 is outside the safe range",
       "; choose a distance inside the safe range or pass --allow-singular"});
  requireRegularOffsets(validity, {0.1, -0.55, -0.6}, true, warnings);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[1].find("offset distance -0.6 is outside the safe range"), std::string::npos);
  EXPECT_NE(warnings[1].find("(kept: --allow-singular)"), std::string::npos);
  // A singular function has been judged by its own check: its offsets are not checked again.
  SupportValidity singular = validity;
  singular.parabolicCrossings = 3;
  warnings.clear();
  requireRegularOffsets(singular, {-5.0}, false, warnings);
  EXPECT_TRUE(warnings.empty());
}

TEST(SupportOffsets, PatchOffsetsMustStayInsideEveryPatchsRange) {
  const SupportFunction h = sphereFunction(1.0);
  SupportPatchSet set;
  set.patches.push_back(
      trianglePatch(h, Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ(), -1.0, 0.8));
  set.patches.push_back(
      trianglePatch(h, -Vector3d::UnitX(), -Vector3d::UnitZ(), -Vector3d::UnitY(), -0.3, 2.0));
  std::vector<std::string> warnings;
  requireRegularPatchOffsets(set, {-0.29, 0.0, 0.79}, false, warnings);
  EXPECT_TRUE(warnings.empty());
  test::expectInputError(
      [&] {
        requireRegularPatchOffsets(set, {0.1, 0.8}, false, warnings);
      },
      {"offset 0.8 is outside the range (-0.3, 0.8) where every patch stays regular",
       "; choose a distance inside it or pass --allow-singular"});
  requireRegularPatchOffsets(set, {-0.3, 1.0}, true, warnings);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("offset -0.3 is outside"), std::string::npos);
  EXPECT_NE(warnings[1].find("(kept: --allow-singular)"), std::string::npos);
}

TEST(SupportOffsets, TessellationDomainIsThePatchOrAGeodesicSphere) {
  EXPECT_EQ(tessellationDomain(std::nullopt, 3).normals.size(), 10u * 64u + 2u);
  SphericalTriangulation patch;
  patch.normals = {Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()};
  patch.triangles = {{0, 1, 2}};
  const SphericalTriangulation domain = tessellationDomain(patch, 3);
  EXPECT_EQ(domain.normals, patch.normals);
  EXPECT_EQ(domain.triangles, patch.triangles);
}

TEST(SupportOffsets, PatchOffsetsAreOneMeshOfThePiecesOnTheOffsetSphere) {
  const double radius = 1.5;
  const SupportFunction h = sphereFunction(radius);
  SupportPatchSet set;
  set.patches.push_back(
      trianglePatch(h, Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ(), -radius, 1e9));
  set.patches.push_back(
      trianglePatch(h, -Vector3d::UnitX(), -Vector3d::UnitZ(), -Vector3d::UnitY(), -radius, 1e9));
  for (const double d : {0.0, 0.25, -0.5}) {
    const TriangleMesh mesh = tessellatePatchOffsets(set, d);
    ASSERT_EQ(mesh.positions.size(), 6u);
    ASSERT_EQ(mesh.normals.size(), 6u);
    ASSERT_EQ(mesh.triangles.size(), 2u);
    // The second piece's triangle indexes its own vertices, after the first piece's.
    for (const TriangleMesh::Index v : mesh.triangles[0]) EXPECT_LT(v, 3u);
    for (const TriangleMesh::Index v : mesh.triangles[1]) EXPECT_GE(v, 3u);
    for (std::size_t v = 0; v < 6; ++v) {
      EXPECT_NEAR(mesh.positions[v].cast<double>().norm(), radius + d, 1e-6) << "vertex " << v;
      const Vector3d normal = set.patches[v / 3].gaussImage.gaussImage.normals[v % 3];
      EXPECT_NEAR((mesh.positions[v].cast<double>() - (radius + d) * normal).norm(), 0.0, 1e-6);
    }
  }
}

}  // namespace
}  // namespace d2vdb
