// buildApproximantField(): fields of generated point sets, polylines, meshes (level set and smooth
// surface) and .vdb files against the known distances of their shapes; the voxel-size rule and
// the messages.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "IoTestSupport.h"
#include "common/Icosphere.h"
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/field/SmoothSurfaceField.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/FieldFromInput.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/PolylineFile.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"

namespace d2vdb {
namespace {

using test::expectInputError;

class FieldFromInputTest : public test::ScratchDirectoryTest {
 protected:
  // loadInput() as buildApproximantField() expects it, then the field.
  static BuiltField build(const std::filesystem::path& path, const FieldBuildOptions& options) {
    LoadOptions load;
    load.field = options.field;
    const InputKinds kinds =
        options.smooth ? InputKinds{InputKind::Mesh}
                       : InputKinds{InputKind::Mesh,  InputKind::PointSet,  InputKind::Field,
                                    InputKind::Curve, InputKind::Polylines, InputKind::Surface};
    return buildApproximantField(loadInput(path, kinds, load), options);
  }

  static FieldBuildOptions withVoxelSize(double voxelSize) {
    FieldBuildOptions options;
    options.voxelSize = voxelSize;
    return options;
  }

  // The level-3 icosphere (vertices on the unit sphere) as an OBJ file.
  std::filesystem::path writeIcosphere() const {
    const test::UnitIcosphere sphere = test::unitIcosphere(3);
    TriangleMesh mesh;
    for (const Eigen::Vector3d& p : sphere.positions) mesh.positions.push_back(p.cast<float>());
    mesh.triangles = sphere.triangles;
    writeMesh(file("icosphere.obj"), mesh);
    return file("icosphere.obj");
  }
};

// The field's estimate of the distance at `x`.
double distanceAt(const ApproximantField& field, const Eigen::Vector3d& x) {
  return std::sqrt(field.squaredDistanceAt(x));
}

TEST_F(FieldFromInputTest, PointSetFieldAndTheVoxelSizeRule) {
  writePointSet(file("points.xyz"), {{0, 0, 0}, {1, 0, 0}, {0, 0.5, 0}});
  const BuiltField given = build(file("points.xyz"), withVoxelSize(0.05));
  EXPECT_EQ(given.inputKind, InputKind::PointSet);
  EXPECT_EQ(given.field.voxelSize(), 0.05);
  EXPECT_FALSE(given.smooth);
  EXPECT_NEAR(distanceAt(given.field, {0.1, 0.0, 0.0}), 0.1, 1e-6);  // float storage

  // The longest side (1) over the resolution.
  FieldBuildOptions resolution;
  resolution.resolution = 20;
  EXPECT_EQ(build(file("points.xyz"), resolution).field.voxelSize(), 1.0 / 20);

  writePointSet(file("one.xyz"), {{1, 2, 3}});
  expectInputError([&] { build(file("one.xyz"), FieldBuildOptions{}); }, {"zero extent"});
  expectInputError([&] { build(file("one.xyz"), FieldBuildOptions{}); }, {"point set"});
  EXPECT_EQ(build(file("one.xyz"), withVoxelSize(0.1)).field.voxelSize(), 0.1);
}

TEST_F(FieldFromInputTest, PolylineFieldOfACircle) {
  Polyline circle;
  circle.closed = true;
  circle.dimension = 2;
  for (int i = 0; i < 400; ++i) {
    const double angle = 2 * kPi * i / 400;
    circle.points.emplace_back(std::cos(angle), std::sin(angle), 0.0);
  }
  writePolyline(file("circle.json"), circle);
  FieldBuildOptions options;
  options.resolution = 40;
  const BuiltField built = build(file("circle.json"), options);
  EXPECT_EQ(built.inputKind, InputKind::Polylines);
  EXPECT_EQ(built.field.voxelSize(), 2.0 / 40);
  // 400 chords are within 3.1e-5 of the circle.
  EXPECT_NEAR(distanceAt(built.field, {1.05, 0.0, 0.0}), 0.05, 1e-4);
  EXPECT_NEAR(distanceAt(built.field, {0.0, -0.93, 0.02}), std::hypot(0.07, 0.02), 1e-4);
}

TEST_F(FieldFromInputTest, MeshFieldsThroughTheLevelSetAndTheSmoothSurface) {
  const std::filesystem::path path = writeIcosphere();
  const BuiltField levelSet = build(path, withVoxelSize(0.04));
  EXPECT_EQ(levelSet.inputKind, InputKind::Mesh);
  EXPECT_TRUE(levelSet.warnings.empty());
  EXPECT_FALSE(levelSet.smooth);
  EXPECT_EQ(levelSet.field.voxelSize(), 0.04);
  // The level-3 icosphere's faces lie within 0.005 of the unit sphere.
  EXPECT_NEAR(distanceAt(levelSet.field, {1.05, 0.0, 0.0}), 0.05, 0.01);
  EXPECT_NEAR(distanceAt(levelSet.field, {0.0, 0.0, -0.95}), 0.05, 0.01);

  FieldBuildOptions smooth = withVoxelSize(0.04);
  smooth.smooth = SmoothSurfaceSource::LoopLimit;
  const BuiltField surface = build(path, smooth);
  EXPECT_EQ(surface.inputKind, InputKind::Mesh);
  ASSERT_TRUE(surface.smooth);
  EXPECT_EQ(surface.smooth->source, SmoothSurfaceSource::LoopLimit);
  EXPECT_EQ(surface.smooth->subdividedFaces, 0u);
  EXPECT_EQ(surface.field.estimator().rfind(kSmoothSurfaceEstimator, 0), 0u);
  EXPECT_NEAR(distanceAt(surface.field, {1.05, 0.0, 0.0}), 0.05, 0.01);

  writePointSet(file("points.xyz"), {{0, 0, 0}, {1, 0, 0}});
  expectInputError(
      [&] {
        LoadOptions load;
        buildApproximantField(loadInput(file("points.xyz"), {InputKind::PointSet}, load), smooth);
      },
      {"points.xyz", "smooth surface"});
}

TEST_F(FieldFromInputTest, LevelSetAndStoredFieldKeepTheirVoxels) {
  PrimitiveLevelSetOptions levelSet;
  levelSet.voxelSize = 0.05;
  writeVdb(file("sphere.vdb"), {primitiveLevelSet(Sphere(Eigen::Vector3d::Zero(), 1.0), levelSet)});
  const BuiltField computed = build(file("sphere.vdb"), withVoxelSize(0.2));
  EXPECT_EQ(computed.inputKind, InputKind::LevelSet);
  EXPECT_EQ(computed.field.voxelSize(), 0.05);
  EXPECT_NEAR(distanceAt(computed.field, {0.0, 1.06, 0.0}), 0.06, 0.005);

  writeField(file("field.vdb"), computed.field);
  const BuiltField stored = build(file("field.vdb"), FieldBuildOptions{});
  EXPECT_EQ(stored.inputKind, InputKind::Field);
  EXPECT_STREQ(inputKindName(stored.inputKind), "field");
  EXPECT_EQ(stored.field.voxelSize(), 0.05);
}

TEST_F(FieldFromInputTest, RefusesSurfacesAndOtherKinds) {
  writeSurfaceJson(
      file("sheet.json"),
      BSplineSurface::clamped(1, 1, 2, 2, {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}}));
  expectInputError([&] { build(file("sheet.json"), FieldBuildOptions{}); },
                   {"is a B-spline surface", "tessellate it first"});
  PrimitiveLevelSetOptions levelSet;
  levelSet.voxelSize = 0.1;
  writeVdb(file("sphere.vdb"), {primitiveLevelSet(Sphere(Eigen::Vector3d::Zero(), 1.0), levelSet)});
  expectInputError(
      [&] {
        buildApproximantField(loadInput(file("sphere.vdb"), {InputKind::VdbGrids}),
                              FieldBuildOptions{});
      },
      {"sphere.vdb"});
}

}  // namespace
}  // namespace d2vdb
