#include "d2vdb/support/SupportPatches.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "SupportTestSupport.h"
#include "common/ExpectInputError.h"
#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

constexpr double kMajor = 2.0;  // R: distance of the tube's centre circle from the axis
constexpr double kMinor = 0.5;  // r: tube radius

// The torus ((R + r cos v) cos u, (R + r cos v) sin u, r sin v) as an outward grid mesh with
// exact unit normals (cos v cos u, cos v sin u, sin v). Outer half (cos v > 0): convex, principal
// radii r and (R + r cos v) / cos v >= R + r. Inner half: saddle, radii r and
// (R + r cos v) / cos v <= -(R - r). The circles v = +-pi/2 (grid rows when `tube` is a multiple
// of 4) are parabolic.
TriangleMesh torus(int around, int tube) {
  TriangleMesh mesh;
  for (int i = 0; i < around; ++i) {
    const double u = 2.0 * kPi * i / around;
    for (int j = 0; j < tube; ++j) {
      const double v = 2.0 * kPi * j / tube;
      const Eigen::Vector3d n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
      const Eigen::Vector3d p((kMajor + kMinor * std::cos(v)) * std::cos(u),
                              (kMajor + kMinor * std::cos(v)) * std::sin(u), kMinor * std::sin(v));
      mesh.positions.push_back(p.cast<float>());
      mesh.normals.push_back(n.cast<float>());
    }
  }
  const auto index = [&](int i, int j) {
    return static_cast<TriangleMesh::Index>((i % around) * tube + (j % tube));
  };
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < tube; ++j) {
      mesh.triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      mesh.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  }
  return mesh;
}

// The torus point with unit normal n on the outer (outer = true) or inner half.
Eigen::Vector3d torusPoint(const Eigen::Vector3d& n, bool outer) {
  const Eigen::Vector3d radial = Eigen::Vector3d(n.x(), n.y(), 0.0).normalized();
  return (outer ? kMajor : -kMajor) * radial + kMinor * n;
}

TEST(SupportPatches, TorusSplitsIntoConvexOuterAndSaddleInnerPatches) {
  const TriangleMesh mesh = torus(96, 48);
  const std::vector<RadiusSigns> classes = classifyTriangles(mesh, "torus", 0.1);
  const auto count = [&](RadiusSigns s) {
    return static_cast<std::size_t>(std::count(classes.begin(), classes.end(), s));
  };
  // Every triangle is classified by the sign of cos v at its centroid (outer convex, inner
  // saddle), except a band around the parabolic circles v = +-pi/2, where one curvature is below
  // 0.1 of the other (|cos v| / (R + r cos v) against 1 / r: |cos v| < 0.44), widened by one ring.
  std::size_t parabolic = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto v : mesh.triangles[t]) centroid += mesh.positions[v].cast<double>() / 3.0;
    const double cosV =
        (std::hypot(centroid.x(), centroid.y()) - kMajor) / kMinor;  // of the centroid, roughly
    if (classes[t] == RadiusSigns::Parabolic) {
      ++parabolic;
      EXPECT_LT(std::abs(cosV), 0.7) << "triangle " << t;
    } else {
      EXPECT_EQ(classes[t], cosV > 0.0 ? RadiusSigns::Convex : RadiusSigns::Saddle) << t;
    }
  }
  EXPECT_EQ(count(RadiusSigns::Concave), 0u);
  EXPECT_GT(parabolic, 0u);

  SupportPatchOptions options;
  options.degree = 16;
  options.parabolicRatio = 0.1;
  const SupportPatchSet set = fitSupportPatches(mesh, options, "torus");
  ASSERT_EQ(set.patches.size(), 2u);
  EXPECT_EQ(set.uncoveredTriangles(), count(RadiusSigns::Parabolic));
  EXPECT_EQ(set.rejectedTriangles, 0u);
  for (const SupportPatch& patch : set.patches) {
    const bool outer = patch.signs == RadiusSigns::Convex;
    EXPECT_TRUE(outer || patch.signs == RadiusSigns::Saddle);
    EXPECT_TRUE(patch.validity.regular());
    EXPECT_EQ(patch.validity.signs, patch.signs);
    // The fitted surface against the exact torus at the patch's normals (the fit's accuracy is
    // limited by the branch points of h = r +- R sqrt(n_x^2 + n_y^2) at the poles, just outside
    // the Gauss image, and by the mesh's float coordinates).
    double worst = 0.0;
    for (const Eigen::Vector3d& n : patch.gaussImage.gaussImage.normals) {
      worst = std::max(worst, (patch.function.point(n) - torusPoint(n, outer)).norm());
    }
    EXPECT_LT(worst, 2e-4) << radiusSignsName(patch.signs);
    // Radii: the tube radius r on both halves; the other is >= R + r (outer) or <= -(R - r).
    // (Second derivatives are least accurate at the edge of the Gauss image: 8% on the saddle.)
    if (outer) {
      EXPECT_NEAR(patch.validity.minRadius, kMinor, 0.005);
      EXPECT_NEAR(patch.validity.safeOffsetMin, -kMinor, 0.005);
      EXPECT_EQ(patch.validity.safeOffsetMax, std::numeric_limits<double>::infinity());
    } else {
      EXPECT_NEAR(patch.validity.safeOffsetMin, -kMinor, 0.05);
      EXPECT_NEAR(patch.validity.safeOffsetMax, kMajor - kMinor, 0.005);
    }
  }
  // The torus's own offsets are regular exactly for -r < d < R - r.
  EXPECT_NEAR(set.safeOffsetMin(), -kMinor, 0.05);
  EXPECT_NEAR(set.safeOffsetMax(), kMajor - kMinor, 0.005);
}

TEST(SupportPatches, ConvexMeshIsOnePatchAndBadInputIsRefused) {
  // The ellipsoid as a geodesic mesh with exact normals: one convex patch.
  const test::Ellipsoid ellipsoid;
  TriangleMesh mesh;
  const SphericalTriangulation sphere = geodesicSphere(3);
  for (const auto& n : sphere.normals) {
    mesh.positions.push_back(ellipsoid.point(n).cast<float>());
    mesh.normals.push_back(n.cast<float>());
  }
  for (const auto& t : sphere.triangles) mesh.triangles.push_back({t[0], t[1], t[2]});
  SupportPatchOptions options;
  options.degree = 8;
  const SupportPatchSet set = fitSupportPatches(mesh, options, "ellipsoid");
  ASSERT_EQ(set.patches.size(), 1u);
  EXPECT_EQ(set.patches[0].signs, RadiusSigns::Convex);
  EXPECT_EQ(set.uncoveredTriangles(), 0u);
  EXPECT_EQ(set.convexTriangles, mesh.triangles.size());

  // A fit that misses the residual bound is cut and refitted, and what still misses it is
  // rejected, never returned.
  options.maxRelativeResidual = 1e-12;
  options.maxSplitDepth = 2;
  const SupportPatchSet strict = fitSupportPatches(mesh, options, "ellipsoid");
  EXPECT_TRUE(strict.patches.empty());
  EXPECT_EQ(strict.rejectedTriangles, mesh.triangles.size());
  EXPECT_EQ(strict.uncoveredTriangles(), mesh.triangles.size());

  test::expectInputError([] { fitSupportPatches(TriangleMesh(), {}, "empty"); }, {"no triangles"});
  TriangleMesh bad = mesh;
  bad.triangles[0][1] = 1u << 30;
  test::expectInputError([&] { fitSupportPatches(bad, {}, "bad"); }, {"refers to vertex"});
}

}  // namespace
}  // namespace d2vdb
