// The squared-distance approximant field against analytic references (issue 3): curvature,
// footpoints and frames on a sphere and a torus, curve fields of a circle and a helix, the
// PDM/TDM/SDM forms against the exact d^2 and its Hessian, answers beyond the band, determinism
// across thread counts, and the exact round trip through standard grids.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "FieldTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/field/Primitives.h"

namespace d2vdb {
namespace {

using test::withThreads;

constexpr double kPi = 3.14159265358979323846;

/// Every active voxel centre of the field's band (world).
std::vector<Eigen::Vector3d> bandCentres(const ApproximantField& field) {
  std::vector<Eigen::Vector3d> centres;
  const auto& grid = *field.distanceGrid();
  for (auto voxel = grid.cbeginValueOn(); voxel; ++voxel) {
    const openvdb::Vec3d w = grid.indexToWorld(voxel.getCoord());
    centres.emplace_back(w.x(), w.y(), w.z());
  }
  return centres;
}

/// Angle in degrees between two lines (directions up to sign).
double lineAngleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::min(1.0, std::abs(a.normalized().dot(b.normalized())));
  return std::acos(c) * 180.0 / kPi;
}

/// The exact Hessian of d^2 at a point with footpoint data `s` (a smooth surface, off the cut
/// locus): 2 (n n^T + sum_i d k_i / (1 + d k_i) e_i e_i^T).
Eigen::Matrix3d exactSquaredDistanceHessian(const SurfacePoint& s) {
  const double d = s.signedDistance;
  return 2.0 *
         (s.normal * s.normal.transpose() + d * s.k1 / (1.0 + d * s.k1) * s.e1 * s.e1.transpose() +
          d * s.k2 / (1.0 + d * s.k2) * s.e2 * s.e2.transpose());
}

struct SurfaceErrors {
  double curvature = 0.0;  // max |k - k_exact| / scale
  double footpoint = 0.0;  // max footpoint error, voxels
  double e1 = 0.0;         // max angle, degrees
  std::size_t flagged = 0;
  std::size_t voxels = 0;
};

template <typename Shape>
SurfaceErrors surfaceErrors(const ApproximantField& field, const Shape& shape,
                            double curvatureScale) {
  SurfaceErrors errors;
  const double h = field.voxelSize();
  for (const Eigen::Vector3d& centre : bandCentres(field)) {
    const Approximant a = field.approximantAt(centre);
    const SurfacePoint exact = shape.closestSurfacePoint(centre);
    ++errors.voxels;
    if (a.flags & (kFlagCutLocus | kFlagDegradedEstimate)) ++errors.flagged;
    errors.curvature = std::max({errors.curvature, std::abs(a.k1 - exact.k1) / curvatureScale,
                                 std::abs(a.k2 - exact.k2) / curvatureScale});
    errors.footpoint = std::max(errors.footpoint, (a.footpoint - exact.point).norm() / h);
    if (std::abs(exact.k1 - exact.k2) > 1e-9) {
      errors.e1 = std::max(errors.e1, lineAngleDegrees(a.tangent, exact.e1));
    }
  }
  return errors;
}

TEST(ApproximantField, SphereOfRadiusFortyVoxels) {
  const double h = 0.025, radius = 40 * h;
  const Sphere sphere(Eigen::Vector3d(0.1, -0.2, 0.05), radius);
  const ApproximantField field =
      ApproximantField::fromLevelSet(primitiveLevelSet(sphere, {h, 3.0}));
  EXPECT_EQ(field.kind(), TargetKind::Surface);
  const SurfaceErrors errors = surfaceErrors(field, sphere, 1.0 / radius);
  std::printf(
      "sphere R = 40 voxels: %zu voxels, max |k - 1/R| = %.4g / R, footpoint %.4g voxel,"
      " %zu flagged\n",
      errors.voxels, errors.curvature, errors.footpoint, errors.flagged);
  EXPECT_LE(errors.curvature, 0.02);
  EXPECT_LE(errors.footpoint, 0.05);
  EXPECT_EQ(errors.flagged, 0u);
  // Normals: the record's normal is the outward radial direction.
  for (const Eigen::Vector3d& centre : bandCentres(field)) {
    const Approximant a = field.approximantAt(centre);
    EXPECT_NEAR(a.distance, sphere.signedDistance(centre), 0.05 * h);
    ASSERT_LT(lineAngleDegrees(a.normal, centre - sphere.centre()), 0.2);
    EXPECT_GT(a.normal.dot(centre - sphere.centre()), 0.0);
  }
}

TEST(ApproximantField, TorusWithRadiiSixtyAndTwentyVoxels) {
  const double h = 0.02;
  const Torus torus(Eigen::Vector3d(0.0, 0.0, 0.0), 60 * h, 20 * h);
  const ApproximantField field = ApproximantField::fromLevelSet(primitiveLevelSet(torus, {h, 3.0}));
  // Both principal curvatures within 3% of the curvature scale 1/r of the tube (k2 passes through
  // zero on the top and bottom circles, so a relative error of k2 alone is undefined there), and
  // within 3% of |k2| itself wherever |k2| is at least half its largest value.
  const double r = 20 * h, R = 60 * h;
  SurfaceErrors errors = surfaceErrors(field, torus, 1.0 / r);
  double relativeK2 = 0.0;
  for (const Eigen::Vector3d& centre : bandCentres(field)) {
    const SurfacePoint exact = torus.closestSurfacePoint(centre);
    if (std::abs(exact.k2) < 0.5 / (R + r)) continue;
    const Approximant a = field.approximantAt(centre);
    relativeK2 = std::max(relativeK2, std::abs(a.k2 - exact.k2) / std::abs(exact.k2));
  }
  std::printf(
      "torus 60/20 voxels: %zu voxels, max |dk| = %.4g / r, max |dk2|/|k2| = %.4g "
      "(|k2| >= half max), footpoint %.4g voxel, e1 %.3g deg, %zu flagged\n",
      errors.voxels, errors.curvature, relativeK2, errors.footpoint, errors.e1, errors.flagged);
  EXPECT_LE(errors.curvature, 0.03);
  EXPECT_LE(relativeK2, 0.03);
  EXPECT_LE(errors.e1, 3.0);
  EXPECT_LE(errors.footpoint, 0.05);
  EXPECT_EQ(errors.flagged, 0u);
}

/// Largest |SDM form at x + delta - exact d^2(x + delta)| over random band points x and offsets
/// |delta| <= 1 voxel, and the largest relative Frobenius error of the form's Hessian against the
/// exact Hessian of d^2 at x where that Hessian is positive semidefinite.
template <typename Shape>
std::pair<double, double> formErrors(const ApproximantField& field, const Shape& shape,
                                     unsigned seed) {
  const double h = field.voxelSize();
  const auto centres = bandCentres(field);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double valueError = 0.0, hessianError = 0.0;
  for (int trial = 0; trial < 4000; ++trial) {
    const Eigen::Vector3d& centre = centres[random() % centres.size()];
    const Eigen::Vector3d x =
        centre + 0.5 * h * Eigen::Vector3d(unit(random), unit(random), unit(random));
    if (std::abs(shape.signedDistance(x)) > field.halfWidth() * h - h) continue;
    Eigen::Vector3d delta;
    do {
      delta = Eigen::Vector3d(unit(random), unit(random), unit(random));
    } while (delta.norm() > 1.0);
    const Eigen::Vector3d y = x + h * delta;
    const QuadraticForm form = field.approximantAt(x).form(ErrorTerm::SDM);
    const double exact = std::pow(shape.signedDistance(y), 2);
    valueError = std::max(valueError, std::abs(form(y) - exact));
    const SurfacePoint s = shape.closestSurfacePoint(x);
    const double d = s.signedDistance;
    if (d * s.k1 >= 0.0 && d * s.k2 >= 0.0) {
      const Eigen::Matrix3d exactHessian = exactSquaredDistanceHessian(s);
      hessianError =
          std::max(hessianError, (form.hessian() - exactHessian).norm() / exactHessian.norm());
    }
  }
  return {valueError, hessianError};
}

TEST(ApproximantField, SdmFormMatchesTheSquaredDistanceToThirdOrder) {
  // Sphere of radius 1 and torus (1, 0.35) at two resolutions: the error of the SDM form one
  // voxel away from the query point must shrink like h^3 (ratio 8 when h halves).
  const Sphere sphere(Eigen::Vector3d::Zero(), 1.0);
  const Torus torus(Eigen::Vector3d::Zero(), 1.0, 0.35);
  for (int shapeIndex = 0; shapeIndex < 2; ++shapeIndex) {
    double previous = 0.0;
    for (const double h : {0.04, 0.02}) {
      const auto grid = shapeIndex == 0 ? primitiveLevelSet(sphere, {h, 3.0})
                                        : primitiveLevelSet(torus, {h, 3.0});
      const ApproximantField field = ApproximantField::fromLevelSet(grid);
      const auto [valueError, hessianError] =
          shapeIndex == 0 ? formErrors(field, sphere, 7) : formErrors(field, torus, 7);
      std::printf("%s h = %g: max |F(x+delta) - d^2| = %.3g = %.3g h^3, Hessian error %.3g%%\n",
                  shapeIndex == 0 ? "sphere" : "torus", h, valueError, valueError / (h * h * h),
                  100.0 * hessianError);
      EXPECT_LE(hessianError, 0.05);
      EXPECT_LE(valueError, 8.0 * h * h * h / (shapeIndex == 0 ? 1.0 : 0.35));
      if (previous > 0.0) {
        EXPECT_GT(previous / valueError, 4.0) << "not third order";
      }
      previous = valueError;
    }
  }
}

}  // namespace
}  // namespace d2vdb
