// loadFitTarget(): the targets of curve and surface fits read from generated files, against what
// was written (points, control points, vertices) and the offsets' known distances; the messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "IoTestSupport.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/FitTarget.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/PolylineFile.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"

namespace d2vdb {
namespace {

using test::expectInputError;

class FitTargetTest : public test::ScratchDirectoryTest {
 protected:
  // The square with corners (+-1, +-1) as a closed 2D polyline.
  std::filesystem::path writeSquare() const {
    Polyline square;
    square.points = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    square.closed = true;
    square.dimension = 2;
    writePolyline(file("square.json"), square);
    return file("square.json");
  }

  // The unit sphere's level set, voxel size 0.05.
  std::filesystem::path writeSphereLevelSet() const {
    PrimitiveLevelSetOptions options;
    options.voxelSize = 0.05;
    const Sphere sphere(Eigen::Vector3d::Zero(), 1.0);
    writeVdb(file("sphere.vdb"), {primitiveLevelSet(sphere, options)});
    return file("sphere.vdb");
  }

  static FitTargetOptions surfaceFit(double offset = 0) {
    FitTargetOptions options;
    options.spline = FitSpline::Surface;
    options.offset = offset;
    return options;
  }
};

TEST_F(FitTargetTest, PolylineSamplesLieOnThePolyline) {
  const std::filesystem::path path = writeSquare();
  const FitTarget target = loadFitTarget(path);
  EXPECT_EQ(target.kind, InputKind::Polylines);
  EXPECT_STREQ(inputKindName(target.kind), "polyline");
  EXPECT_EQ(target.pieces, 4u);
  EXPECT_TRUE(target.closed);
  EXPECT_EQ(target.dimension, 2);
  ASSERT_NE(target.target, nullptr);
  EXPECT_EQ(target.offset, nullptr);
  EXPECT_EQ(&target.fitTarget(), target.target.get());
  EXPECT_NE(target.target->describe().find(path.string()), std::string::npos);
  // Perimeter 8 sampled every 8 / 2000 at most.
  EXPECT_GE(target.points.size(), 2000u);
  for (const Eigen::Vector3d& p : target.points) {
    EXPECT_NEAR(std::max(std::abs(p.x()), std::abs(p.y())), 1.0, 1e-12);
    EXPECT_EQ(p.z(), 0.0);
  }
}

TEST_F(FitTargetTest, OffsetOfACurveIsAtTheOffsetDistance) {
  FitTargetOptions options;
  options.offset = 0.25;
  const FitTarget target = loadFitTarget(writeSquare(), options);
  ASSERT_NE(target.offset, nullptr);
  EXPECT_EQ(&target.fitTarget(), target.offset.get());
  // (2, 0) is 1 from the square's side x = 1, so 0.75 from the offset.
  EXPECT_NEAR(target.fitTarget().approximantAt({2.0, 0.0, 0.0}).distance, 0.75, 1e-12);
}

TEST_F(FitTargetTest, BSplineCurveSamplesLieOnItsControlPolygon) {
  // A degree-1 B-spline is its control polygon: (0, 0, 0) - (1, 0, 0) - (1, 1, 1).
  writeCurveJson(file("bent.json"), BSplineCurve::clamped(1, {{0, 0, 0}, {1, 0, 0}, {1, 1, 1}}));
  const FitTarget target = loadFitTarget(file("bent.json"));
  EXPECT_EQ(target.kind, InputKind::Curve);
  EXPECT_EQ(target.pieces, 3u);
  EXPECT_FALSE(target.closed);
  EXPECT_EQ(target.dimension, 3);
  ASSERT_FALSE(target.points.empty());
  EXPECT_LT(target.points.front().norm(), 1e-15);
  EXPECT_LT((target.points.back() - Eigen::Vector3d(1, 1, 1)).norm(), 1e-12);
  for (const Eigen::Vector3d& p : target.points) {
    const bool firstLeg = std::abs(p.y()) < 1e-12 && std::abs(p.z()) < 1e-12;
    const bool secondLeg = std::abs(p.x() - 1.0) < 1e-12 && std::abs(p.y() - p.z()) < 1e-12;
    EXPECT_TRUE(firstLeg || secondLeg) << p.transpose();
  }
}

TEST_F(FitTargetTest, PointCloudGivesThePointsWritten) {
  const std::vector<Eigen::Vector3d> flat = {{0.1, 0.2, 0}, {-1.5, 2.25, 0}, {3, -0.7, 0}};
  writePointSet(file("flat.xyz"), flat);
  const FitTarget planar = loadFitTarget(file("flat.xyz"));
  EXPECT_EQ(planar.kind, InputKind::PointSet);
  EXPECT_TRUE(planar.points == flat);
  EXPECT_EQ(planar.dimension, 2);
  EXPECT_EQ(planar.target, nullptr);

  const std::vector<Eigen::Vector3d> spatial = {{0.1, 0.2, 0.3}, {-1.5, 2.25, 0}, {3, -0.7, 1}};
  writePointSet(file("spatial.xyz"), spatial);
  const FitTarget cloud = loadFitTarget(file("spatial.xyz"), surfaceFit());
  EXPECT_TRUE(cloud.points == spatial);
  EXPECT_EQ(cloud.dimension, 3);

  FitTargetOptions offset;
  offset.offset = 0.1;
  expectInputError([&] { loadFitTarget(file("flat.xyz"), offset); },
                   {"--offset needs a curve target (a B-spline or polyline .json), not a points "
                    "target"});
  expectInputError([&] { loadFitTarget(file("flat.xyz"), surfaceFit(0.1)); },
                   {"--offset needs a field or B-spline surface target, not a point cloud"});
}

TEST_F(FitTargetTest, BSplineSurfaceSamplesItsParameterGrid) {
  // The bilinear patch z = 0 over [0, 2] x [0, 1], normal +z.
  writeSurfaceJson(
      file("sheet.json"),
      BSplineSurface::clamped(1, 1, 2, 2, {{0, 0, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}}));
  const FitTarget sheet = loadFitTarget(file("sheet.json"), surfaceFit());
  EXPECT_EQ(sheet.kind, InputKind::Surface);
  ASSERT_EQ(sheet.points.size(), 101u * 101u);
  for (const Eigen::Vector3d& p : sheet.points) {
    EXPECT_EQ(p.z(), 0.0);
    EXPECT_TRUE(p.x() >= 0.0 && p.x() <= 2.0 && p.y() >= 0.0 && p.y() <= 1.0) << p.transpose();
  }
  EXPECT_NE(std::find(sheet.points.begin(), sheet.points.end(), Eigen::Vector3d(2, 1, 0)),
            sheet.points.end());

  const FitTarget offset = loadFitTarget(file("sheet.json"), surfaceFit(0.1));
  ASSERT_NE(offset.offset, nullptr);
  EXPECT_NEAR(offset.fitTarget().approximantAt({1.0, 0.5, 1.0}).distance, 0.9, 1e-12);
}

TEST_F(FitTargetTest, LevelSetSamplesLieOnTheSphere) {
  const std::filesystem::path path = writeSphereLevelSet();
  const FitTarget sphere = loadFitTarget(path, surfaceFit());
  EXPECT_EQ(sphere.kind, InputKind::Field);
  ASSERT_NE(sphere.target, nullptr);
  ASSERT_GT(sphere.points.size(), 1000u);
  EXPECT_LE(sphere.points.size(), 2u * 200000u);
  for (const Eigen::Vector3d& p : sphere.points) EXPECT_NEAR(p.norm(), 1.0, 0.01);

  // A curve fit takes the field as it is, without points, and no offset of a surface.
  const FitTarget field = loadFitTarget(path);
  EXPECT_EQ(field.kind, InputKind::Field);
  EXPECT_TRUE(field.points.empty());
  FitTargetOptions offset;
  offset.offset = 0.1;
  expectInputError([&] { loadFitTarget(path, offset); },
                   {"--offset needs a curve target", "not a field target"});
}

TEST_F(FitTargetTest, RefusesMeshesWithThePurpose) {
  TriangleMesh tetrahedron;
  tetrahedron.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetrahedron.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  writeMesh(file("tetrahedron.obj"), tetrahedron);
  expectInputError([&] { loadFitTarget(file("tetrahedron.obj"), surfaceFit()); },
                   {"is a triangle mesh", "d2vdb mesh2sdf"});
  FitTargetOptions curve;
  curve.purpose = "the target of the test";
  expectInputError([&] { loadFitTarget(file("tetrahedron.obj"), curve); },
                   {"the target of the test"});
}

}  // namespace
}  // namespace d2vdb
