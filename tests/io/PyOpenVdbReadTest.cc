// Every kind of .vdb file the engine writes opens in Debian's pyopenvdb (python3-openvdb, the
// bindings VFX users script with): readAllGridMetadata() and readAll() succeed, and every grid,
// its value type, active voxel count and every active value equal what d2vdb's own reader reads
// from the same file. Level sets (full and half floats) and approximant fields of every target
// kind (surface, curve, points; full and half floats).
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "IoTestSupport.h"
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/CurveTarget.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/VdbFile.h"
#include "field/ApproximantFieldTestSupport.h"

namespace d2vdb {
namespace {

// One grid as a reader saw it: its value type and every active voxel's values.
struct GridDump {
  std::string valueType;
  std::uint64_t activeVoxels = 0;
  std::map<std::array<int, 3>, std::vector<double>> values;
};
using FileDump = std::map<std::string, GridDump>;  // by grid name (pyopenvdb reorders them)

// What pyopenvdb reads (tests/io/pyopenvdb_dump.py); fails the test when it cannot read the file.
FileDump readWithPyOpenVdb(const std::filesystem::path& file) {
  const std::filesystem::path out = file.string() + ".dump";
  const std::filesystem::path err = file.string() + ".err";
  const std::string command = std::string("/usr/bin/python3 '") + D2VDB_SOURCE_DIR +
                              "/tests/io/pyopenvdb_dump.py' '" + file.string() + "' >'" +
                              out.string() + "' 2>'" + err.string() + "'";
  const int status = std::system(command.c_str());
  std::ifstream errors(err);
  std::stringstream message;
  message << errors.rdbuf();
  EXPECT_EQ(status, 0) << file << ": " << message.str();
  FileDump dump;
  GridDump* current = nullptr;
  std::ifstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    if (line.rfind("grid ", 0) == 0) {
      std::string keyword, name;
      GridDump grid;
      fields >> keyword >> name >> grid.valueType >> grid.activeVoxels;
      current = &dump[name];
      *current = grid;
      continue;
    }
    std::array<int, 3> ijk{};
    fields >> ijk[0] >> ijk[1] >> ijk[2];
    std::vector<double> values;
    for (double v = 0; fields >> v;) values.push_back(v);
    if (current != nullptr) current->values[ijk] = values;
  }
  return dump;
}

template <class GridT, class ToDoubles>
bool dumpAs(const openvdb::GridBase& base, const char* typeName, ToDoubles toDoubles,
            GridDump& dump) {
  const auto* grid = dynamic_cast<const GridT*>(&base);
  if (grid == nullptr) return false;
  dump.valueType = typeName;
  dump.activeVoxels = grid->activeVoxelCount();
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    // Active tiles hold their value at every voxel they cover.
    const openvdb::CoordBBox box = it.getBoundingBox();
    for (auto ijk = box.begin(); ijk; ++ijk) {
      dump.values[{(*ijk).x(), (*ijk).y(), (*ijk).z()}] = toDoubles(*it);
    }
  }
  return true;
}

// What d2vdb's own reader reads from `file`, in pyopenvdb's type names.
FileDump readWithD2vdb(const std::filesystem::path& file) {
  FileDump dump;
  for (const openvdb::GridBase::Ptr& grid : readAllGrids(file)) {
    GridDump entry;
    const bool known =
        dumpAs<openvdb::FloatGrid>(
            *grid, "float", [](float v) { return std::vector<double>{v}; }, entry) ||
        dumpAs<openvdb::Vec3SGrid>(
            *grid, "vec3s",
            [](const openvdb::Vec3s& v) {
              return std::vector<double>{v.x(), v.y(), v.z()};
            },
            entry) ||
        dumpAs<openvdb::BoolGrid>(
            *grid, "bool", [](bool v) { return std::vector<double>{v ? 1.0 : 0.0}; }, entry);
    EXPECT_TRUE(known) << file << ": grid '" << grid->getName() << "' has type "
                       << grid->valueType() << ", which pyopenvdb 10 cannot read";
    dump[grid->getName()] = entry;
  }
  return dump;
}

class PyOpenVdbReadTest : public test::ScratchDirectoryTest {
 protected:
  // pyopenvdb reads `file` and sees exactly what d2vdb's reader sees.
  void expectSameAsPyOpenVdb(const std::filesystem::path& file) {
    SCOPED_TRACE(file.filename().string());
    const FileDump ours = readWithD2vdb(file);
    const FileDump theirs = readWithPyOpenVdb(file);
    ASSERT_EQ(theirs.size(), ours.size());
    for (const auto& [name, grid] : ours) {
      SCOPED_TRACE("grid " + name);
      ASSERT_EQ(theirs.count(name), 1u);
      const GridDump& seen = theirs.at(name);
      EXPECT_EQ(seen.valueType, grid.valueType);
      EXPECT_EQ(seen.activeVoxels, grid.activeVoxels);
      EXPECT_GT(grid.values.size(), 0u);
      EXPECT_TRUE(seen.values == grid.values) << seen.values.size() << " values read by pyopenvdb, "
                                              << grid.values.size() << " by d2vdb, or some differ";
    }
  }

  static VdbWriteOptions halfFloats() {
    VdbWriteOptions options;
    options.halfFloat = true;
    return options;
  }
};

TEST_F(PyOpenVdbReadTest, LevelSets) {
  const openvdb::FloatGrid::Ptr sphere = primitiveLevelSet(Sphere({0.1, 0.0, -0.2}, 0.7), {0.05});
  writeVdb(file("sphere.vdb"), {sphere});
  expectSameAsPyOpenVdb(file("sphere.vdb"));
  writeVdb(file("sphere-half.vdb"), {sphere}, halfFloats());
  expectSameAsPyOpenVdb(file("sphere-half.vdb"));
  VdbWriteOptions uncompressed;
  uncompressed.blosc = false;
  writeVdb(file("sphere-raw.vdb"), {sphere}, uncompressed);
  expectSameAsPyOpenVdb(file("sphere-raw.vdb"));
}

TEST_F(PyOpenVdbReadTest, SurfaceFields) {
  const ApproximantField field =
      ApproximantField::fromLevelSet(primitiveLevelSet(Torus({0, 0, 0}, 0.8, 0.3), {0.05, 3.0}));
  writeField(file("torus-field.vdb"), field);
  expectSameAsPyOpenVdb(file("torus-field.vdb"));
  writeField(file("torus-field-half.vdb"), field, halfFloats());
  expectSameAsPyOpenVdb(file("torus-field-half.vdb"));
}

TEST_F(PyOpenVdbReadTest, CurveAndPointFields) {
  Polyline circle;
  circle.closed = true;
  for (int i = 0; i < 300; ++i) {
    const double angle = 2.0 * kPi * i / 300;
    circle.points.emplace_back(0.6 * std::cos(angle), 0.6 * std::sin(angle), 0.1 * angle);
  }
  const ApproximantField curve = ApproximantField::fromCurve(CurveTarget(circle), 0.04, 3.0);
  writeField(file("curve-field.vdb"), curve);
  expectSameAsPyOpenVdb(file("curve-field.vdb"));
  writeField(file("curve-field-half.vdb"), curve, halfFloats());
  expectSameAsPyOpenVdb(file("curve-field-half.vdb"));
  const ApproximantField points = ApproximantField::fromPoints(
      test::randomPoints(Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)),
                         100),
      0.05, 2.0);
  writeField(file("points-field.vdb"), points);
  expectSameAsPyOpenVdb(file("points-field.vdb"));
}

}  // namespace
}  // namespace d2vdb
