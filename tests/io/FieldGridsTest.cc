// Approximant fields as standard OpenVDB grids and .vdb files (FieldGrids.h, FieldFile.h): the
// round trip gives the same answers bit for bit at every level (bunny, torus, rotated grid, curve,
// points); companion grids are matched to the band voxel by voxel, checked against a field built
// directly from the same analytic data and against the analytic shape; bad grids are refused.
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/io/FieldGrids.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "IoTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/field/FieldBand.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/VdbFile.h"
#include "field/ApproximantFieldTestSupport.h"
#include "field/FieldTestSupport.h"

namespace d2vdb {
namespace {

using test::bandCenters;
using test::expectSameAnswers;
using test::randomPoints;

class FieldGridsTest : public test::ScratchDirectoryTest {};

/// Random points of the domain plus points off the target at distances growing geometrically
/// (so that every coarse level answers some), and how many of them each level answered.
std::vector<Eigen::Vector3d> pointsAcrossLevels(const ApproximantField& field,
                                                std::map<int, int>& levels) {
  std::vector<Eigen::Vector3d> points = randomPoints(field.domain(), 3000, 5);
  const auto centers = bandCenters(field);
  const double h = field.voxelSize();
  for (std::size_t i = 0; i < centers.size(); i += 97) {
    const Approximant a = field.approximantAt(centers[i]);
    const double side = a.distance >= 0.0 ? 1.0 : -1.0;
    for (double d = 2.0; d < 1000.0; d *= 1.6) {
      const Eigen::Vector3d p = a.footpoint + side * d * h * a.normal;
      if (field.domain().contains(p)) points.push_back(p);
    }
  }
  ApproximantField::Accessor accessor(field);
  for (const Eigen::Vector3d& p : points) {
    accessor.approximantAt(p);
    ++levels[accessor.lastLevel()];
  }
  return points;
}

/// The field after fieldToGrids() -> fieldFromGrids(), and after writeField() -> readField(),
/// answers as the field itself at the band's voxel centres and at points of every level; the
/// distance grid comes back bit for bit.
void expectExactRoundTrip(const ApproximantField& field, const std::filesystem::path& file,
                          int minimumLevels) {
  std::map<int, int> levels;
  const auto points = pointsAcrossLevels(field, levels);
  int populated = 0;
  for (const auto& [level, count] : levels) populated += count >= 20 ? 1 : 0;
  EXPECT_GE(populated, minimumLevels) << "the points do not reach enough levels";

  const openvdb::GridPtrVec grids = fieldToGrids(field);
  const ApproximantField loaded = fieldFromGrids(grids, "test grids");
  expectSameAnswers(field, loaded, points);
  test::expectBitwiseIdentical(*field.distanceGrid(), *loaded.distanceGrid());
  EXPECT_EQ(loaded.statistics().samples, field.statistics().samples);
  // Stored as the float background: the same up to float rounding.
  EXPECT_NEAR(loaded.halfWidth(), field.halfWidth(), 1e-6 * field.halfWidth());
  EXPECT_EQ(loaded.estimator(), field.estimator());
  EXPECT_EQ(loaded.domain().min(), field.domain().min());
  EXPECT_EQ(loaded.domain().max(), field.domain().max());

  writeField(file, field);
  const ApproximantField read = readField(file);
  expectSameAnswers(field, read, points);
  // The coarse levels, rebuilt by the loaded fields, are those of the original.
  ASSERT_EQ(read.levelCount(), field.levelCount());
  for (std::size_t i = 1; i < field.statistics().levels.size(); ++i) {
    EXPECT_EQ(read.statistics().levels[i].activeVoxels, field.statistics().levels[i].activeVoxels);
  }
}

TEST_F(FieldGridsTest, BunnyRoundTripGivesTheSameAnswersAtEveryLevel) {
  const auto grid = readLevelSet(std::filesystem::path(D2VDB_SOURCE_DIR) / "volumes" / "bunny.vdb");
  const ApproximantField field = ApproximantField::fromLevelSet(grid);
  expectExactRoundTrip(field, file("bunny_field.vdb"), 5);
}

TEST_F(FieldGridsTest, TorusAndRotatedTorusRoundTrips) {
  const Torus torus(Eigen::Vector3d(0.1, 0.0, 0.0), 1.0, 0.35);
  auto grid = primitiveLevelSet(torus, {0.03, 3.0});
  expectExactRoundTrip(ApproximantField::fromLevelSet(grid), file("torus.vdb"), 4);
  // The same level set under a rotated transform (directions go through the index frame).
  auto rotated = grid->deepCopy();
  rotated->transform().postRotate(0.4, openvdb::math::Z_AXIS);
  rotated->transform().postRotate(-0.3, openvdb::math::X_AXIS);
  expectExactRoundTrip(ApproximantField::fromLevelSet(rotated), file("rotated.vdb"), 4);
}

TEST_F(FieldGridsTest, CurveAndPointFieldsRoundTrip) {
  Polyline circle;
  circle.closed = true;
  for (int i = 0; i < 500; ++i) {
    const double angle = 2.0 * kPi * i / 500;
    circle.points.emplace_back(0.6 * std::cos(angle), 0.6 * std::sin(angle), 0.0);
  }
  expectExactRoundTrip(ApproximantField::fromCurve(CurveTarget(circle), 0.03, 3.0),
                       file("curve.vdb"), 3);
  const ApproximantField points = ApproximantField::fromPoints(
      randomPoints(Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)), 200),
      0.05, 2.0);
  expectExactRoundTrip(points, file("points.vdb"), 3);
}

/// Float-rounded vector, as grids hold it.
Eigen::Vector3d asFloat(const Eigen::Vector3d& v) {
  return v.cast<float>().cast<double>();
}

// Grids made by hand from an analytic torus, each companion written voxel by voxel in a shuffled
// order into its own tree, and listed in another order beside unrelated grids: the field read from
// them equals the field built directly from the same per-voxel data (FieldBand), and matches the
// torus within the records' quantisation.
TEST_F(FieldGridsTest, CompanionGridsArePairedVoxelByVoxel) {
  const double h = 0.03;
  const Torus torus(Eigen::Vector3d(0.05, -0.02, 0.0), 0.9, 0.3);
  const auto levelSet = primitiveLevelSet(torus, {h, 3.0});
  const auto exact = [&](const Eigen::Vector3d& center) {
    const SurfacePoint s = torus.closestSurfacePoint(center);
    Approximant a;
    a.kind = TargetKind::Surface;
    a.distance = static_cast<float>(s.signedDistance);
    a.normal = asFloat(s.normal);
    a.tangent = asFloat(s.e1);
    a.k1 = static_cast<float>(s.k1);
    a.k2 = static_cast<float>(s.k2);
    return a;
  };
  FieldBand band = FieldBand::activeVoxelsOf(TargetKind::Surface, levelSet);
  band.setApproximants(
          [&](const openvdb::Coord&, const Eigen::Vector3d& center) { return exact(center); })
      .setEstimator("exact torus")
      .setLabel("exact torus");
  const ApproximantField direct = ApproximantField::fromBand(band);

  // Hand-made grids.
  std::vector<openvdb::Coord> voxels;
  for (auto voxel = direct.distanceGrid()->cbeginValueOn(); voxel; ++voxel) {
    voxels.push_back(voxel.getCoord());
  }
  std::shuffle(voxels.begin(), voxels.end(), std::mt19937(3));
  auto distance = direct.distanceGrid()->deepCopy();
  distance->insertMeta(kFieldKindMetadata, openvdb::StringMetadata("surface"));
  distance->insertMeta(kFieldEstimatorMetadata, openvdb::StringMetadata("exact torus"));
  distance->insertMeta(kFieldVersionMetadata, openvdb::Int32Metadata(kFieldFormatVersion));
  const auto toVec3d = [](const Eigen::Vector3d& v) { return openvdb::Vec3d(v.x(), v.y(), v.z()); };
  distance->insertMeta(kFieldDomainMinMetadata,
                       openvdb::Vec3DMetadata(toVec3d(direct.domain().min())));
  distance->insertMeta(kFieldDomainMaxMetadata,
                       openvdb::Vec3DMetadata(toVec3d(direct.domain().max())));
  const auto make = [&](auto grid, const std::string& name) {
    grid->setTransform(distance->transform().copy());
    grid->setName(name);
    return grid;
  };
  auto normal = make(openvdb::Vec3SGrid::create(), "normal");
  auto e1 = make(openvdb::Vec3SGrid::create(), "e1");
  auto k1 = make(openvdb::FloatGrid::create(), "k1");
  auto k2 = make(openvdb::FloatGrid::create(), "k2");
  auto flags = make(openvdb::FloatGrid::create(), "flags");
  const auto toVec3s = [](const Eigen::Vector3d& v) {
    return openvdb::Vec3s(static_cast<float>(v.x()), static_cast<float>(v.y()),
                          static_cast<float>(v.z()));
  };
  for (const openvdb::Coord& ijk : voxels) {
    const openvdb::Vec3d w = distance->indexToWorld(ijk);
    const Approximant a = exact(Eigen::Vector3d(w.x(), w.y(), w.z()));
    normal->tree().setValueOn(ijk, toVec3s(a.normal));
    e1->tree().setValueOn(ijk, toVec3s(a.tangent));
    k1->tree().setValueOn(ijk, static_cast<float>(a.k1));
    k2->tree().setValueOn(ijk, static_cast<float>(a.k2));
    flags->tree().setValueOn(ijk, 0.0f);
  }
  auto unrelated = openvdb::FloatGrid::create(1.0f);
  unrelated->setName("density");
  unrelated->tree().setValueOn(openvdb::Coord(0, 0, 0), 0.5f);
  const openvdb::GridPtrVec grids{flags, k2, unrelated, e1, distance, normal, k1};
  const ApproximantField loaded = fieldFromGrids(grids, "hand-made grids");
  expectSameAnswers(direct, loaded, randomPoints(direct.domain(), 2000));

  // Against the torus: a voxel paired with another voxel's data would be off by degrees.
  double normalError = 0.0, curvatureError = 0.0, distanceError = 0.0;
  ApproximantField::Accessor accessor(loaded);
  for (const Eigen::Vector3d& center : bandCenters(loaded)) {
    const Approximant a = accessor.approximantAt(center);
    const SurfacePoint s = torus.closestSurfacePoint(center);
    normalError = std::max(normalError, std::acos(std::min(1.0, a.normal.dot(s.normal))));
    curvatureError =
        std::max({curvatureError, std::abs(a.k1 - s.k1) * 0.3, std::abs(a.k2 - s.k2) * 0.3});
    distanceError = std::max(distanceError, std::abs(a.distance - s.signedDistance) / h);
  }
  EXPECT_LT(normalError * 180.0 / kPi, 0.01);  // octahedral 2 x 16 bits
  EXPECT_LT(curvatureError, 1e-3);             // half floats
  EXPECT_LT(distanceError, 1e-5);              // floats
}

TEST_F(FieldGridsTest, RejectsBadGridsWithClearErrors) {
  const double h = 0.05;
  const Sphere sphere(Eigen::Vector3d::Zero(), 0.6);
  const ApproximantField field =
      ApproximantField::fromLevelSet(primitiveLevelSet(sphere, {h, 3.0}));
  const openvdb::GridPtrVec grids = fieldToGrids(field);
  const auto expectError = [](const openvdb::GridPtrVec& input, const std::string& fragment) {
    test::expectInputError([&] { fieldFromGrids(input, "bad.vdb"); }, {"bad.vdb", fragment});
  };
  // A missing companion grid.
  openvdb::GridPtrVec missing;
  for (const auto& grid : grids) {
    if (grid->getName() != "k1") missing.push_back(grid);
  }
  expectError(missing, "'k1' is missing");
  // A companion grid with another topology, type or transform.
  openvdb::GridPtrVec mismatched, retyped, moved;
  for (const auto& grid : grids) {
    if (grid->getName() == "k2") {
      auto copy = openvdb::gridPtrCast<openvdb::FloatGrid>(grid)->deepCopy();
      copy->tree().setValueOn(openvdb::Coord(1000, 0, 0), 0.0f);
      mismatched.push_back(copy);
      auto wrongType = openvdb::Int32Grid::create();
      wrongType->setName("k2");
      retyped.push_back(wrongType);
      auto shifted = openvdb::gridPtrCast<openvdb::FloatGrid>(grid)->deepCopy();
      shifted->transform().postTranslate(openvdb::Vec3d(0.01, 0.0, 0.0));
      moved.push_back(shifted);
    } else {
      mismatched.push_back(grid);
      retyped.push_back(grid);
      moved.push_back(grid);
    }
  }
  expectError(mismatched, "does not share");
  expectError(retyped, "expected");
  expectError(moved, "different transform");
  // NaN in a companion grid; a normal that is not a unit vector.
  openvdb::GridPtrVec poisoned, stretched;
  for (const auto& grid : grids) {
    if (grid->getName() == "k1") {
      auto copy = openvdb::gridPtrCast<openvdb::FloatGrid>(grid)->deepCopy();
      copy->tree().setValueOnly(copy->cbeginValueOn().getCoord(), std::nanf(""));
      poisoned.push_back(copy);
    } else {
      poisoned.push_back(grid);
    }
    if (grid->getName() == "normal") {
      auto copy = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid)->deepCopy();
      copy->tree().setValueOnly(copy->cbeginValueOn().getCoord(), openvdb::Vec3s(2, 0, 0));
      stretched.push_back(copy);
    } else {
      stretched.push_back(grid);
    }
  }
  expectError(poisoned, "non-finite");
  expectError(stretched, "not unit vectors");
  // Unknown version and kind, no field and no level set.
  auto versioned = openvdb::gridPtrCast<openvdb::FloatGrid>(grids.front())->copy();
  versioned->insertMeta(kFieldVersionMetadata, openvdb::Int32Metadata(7));
  openvdb::GridPtrVec future(grids);
  future.front() = versioned;
  expectError(future, "version 7");
  auto unknown = openvdb::gridPtrCast<openvdb::FloatGrid>(grids.front())->copy();
  unknown->insertMeta(kFieldKindMetadata, openvdb::StringMetadata("volume"));
  openvdb::GridPtrVec strange(grids);
  strange.front() = unknown;
  expectError(strange, "unknown field kind 'volume'");
  expectError({openvdb::Int32Grid::create()}, "neither an approximant field nor");
}

TEST_F(FieldGridsTest, ReadsVersionOneFilesWithInt32FlagsAndRefusesBadFlags) {
  // Version 1 of the layout stored the flags as Int32 (pyopenvdb cannot open that type); such
  // grids give the same field as the float flags of today's layout. Some voxels carry flags.
  const ApproximantField field = ApproximantField::fromLevelSet(
      primitiveLevelSet(Torus(Eigen::Vector3d::Zero(), 0.7, 0.25), {0.04, 3.0}));
  openvdb::GridPtrVec current = fieldToGrids(field), versionOne, fractional;
  for (auto& grid : current) {
    if (grid->getName() == "flags") {
      const auto flags = openvdb::gridPtrCast<openvdb::FloatGrid>(grid)->deepCopy();
      ASSERT_TRUE(flags) << "flags are stored as float";
      int n = 0;
      for (auto value = flags->beginValueOn(); value; ++value, ++n) {
        if (n % 7 == 0) value.setValue(static_cast<float>(kFlagDegradedEstimate | kFlagCutLocus));
      }
      auto old = openvdb::Int32Grid::create(0);
      old->setTransform(flags->transform().copy());
      old->setName("flags");
      for (auto value = flags->cbeginValueOn(); value; ++value) {
        old->tree().setValue(value.getCoord(), static_cast<std::int32_t>(*value));
      }
      auto bad = flags->deepCopy();
      bad->tree().setValueOnly(bad->cbeginValueOn().getCoord(), 0.5f);
      grid = flags;
      versionOne.push_back(old);
      fractional.push_back(bad);
    } else if (grid == current.front()) {
      auto distance = openvdb::gridPtrCast<openvdb::FloatGrid>(grid)->copy();
      distance->insertMeta(kFieldVersionMetadata, openvdb::Int32Metadata(1));
      versionOne.push_back(distance);
      fractional.push_back(grid);
    } else {
      versionOne.push_back(grid);
      fractional.push_back(grid);
    }
  }
  const ApproximantField today = fieldFromGrids(current, "version2.vdb");
  const ApproximantField loaded = fieldFromGrids(versionOne, "version1.vdb");
  std::size_t flagged = 0;
  for (const Eigen::Vector3d& p : bandCenters(today)) {
    const Approximant a = loaded.approximantAt(p);
    EXPECT_EQ(a.flags, today.approximantAt(p).flags);
    flagged += (a.flags & kFlagDegradedEstimate) != 0 ? 1 : 0;
  }
  EXPECT_GT(flagged, 0u);
  expectSameAnswers(today, loaded, bandCenters(today));
  test::expectInputError([&] { fieldFromGrids(fractional, "bad.vdb"); },
                         {"bad.vdb", "'flags'", "whole number"});
}

}  // namespace
}  // namespace d2vdb
