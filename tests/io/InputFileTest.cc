// loadInput(): every kind recognised by its content whatever the extension, the extension where
// the content cannot tell, which kind a file becomes for which caller, and clear errors for
// missing, empty, unknown, truncated and unwanted files. The references are the format readers
// themselves on correctly named copies and the values written.
#include "d2vdb/io/InputFile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/PolylineFile.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"
#include "io/IoTestSupport.h"

namespace d2vdb {
namespace {

using Eigen::Vector3d;
using test::expectInputError;
using test::sameBits;

constexpr InputKinds kEveryKind = {InputKind::Mesh,  InputKind::PointSet, InputKind::Field,
                                   InputKind::Curve, InputKind::Surface,  InputKind::Polylines};

class InputFileTest : public test::ScratchDirectoryTest {
 protected:
  // Copies `from` byte for byte to `name` in the scratch directory and returns the copy's path.
  std::filesystem::path copyAs(const std::filesystem::path& from, const std::string& name) const {
    return write(name, test::readWholeFile(from));
  }

  // A tetrahedron, every face outward (closed, 4 vertices, 4 triangles).
  static TriangleMesh tetrahedron() {
    TriangleMesh mesh;
    mesh.positions = {{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.1f, 0.2f, 1.3f}};
    mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    return mesh;
  }

  static openvdb::FloatGrid::Ptr sphereLevelSet() {
    return primitiveLevelSet(Sphere(Vector3d(0.1, 0.2, -0.1), 1.0), {0.1, 3.0});
  }
};

void expectSameMesh(const TriangleMesh& actual, const TriangleMesh& expected) {
  ASSERT_EQ(actual.positions.size(), expected.positions.size());
  for (std::size_t v = 0; v < expected.positions.size(); ++v) {
    EXPECT_EQ(actual.positions[v], expected.positions[v]) << "vertex " << v;
  }
  EXPECT_EQ(actual.triangles, expected.triangles);
}

void expectSamePoints(const std::vector<Vector3d>& actual, const std::vector<Vector3d>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_TRUE(sameBits(actual[i][axis], expected[i][axis])) << "point " << i;
    }
  }
}

// Queries both fields at points around the unit sphere; the answers must agree bit for bit.
void expectSameAnswers(const ApproximantField& actual, const ApproximantField& expected) {
  ApproximantField::Accessor a(actual), b(expected);
  for (int i = 0; i < 50; ++i) {
    const double t = 0.37 * i, s = 0.11 * i;
    const Vector3d point = Vector3d(0.1, 0.2, -0.1) +
                           (0.9 + 0.004 * i) * Vector3d(std::cos(t) * std::cos(s),
                                                        std::sin(t) * std::cos(s), std::sin(s));
    const Approximant x = a.approximantAt(point), y = b.approximantAt(point);
    EXPECT_TRUE(sameBits(x.distance, y.distance)) << "at query " << i;
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_TRUE(sameBits(x.footpoint[axis], y.footpoint[axis])) << "at query " << i;
      EXPECT_TRUE(sameBits(x.normal[axis], y.normal[axis])) << "at query " << i;
    }
  }
}

TEST_F(InputFileTest, MeshesAreRecognizedByContentWhateverTheExtension) {
  const TriangleMesh mesh = tetrahedron();
  writeMesh(file("t.obj"), mesh);
  writeMesh(file("t.ply"), mesh);
  writeMesh(file("binary.stl"), mesh);
  writeMesh(file("ascii.stl"), mesh, MeshWriteOptions{false});
  struct Case {
    std::string original, misleading;
    MeshFormat format;
  };
  for (const Case& c : {Case{"t.obj", "obj-named.xyz", MeshFormat::Obj},
                        Case{"t.ply", "ply-named.stl", MeshFormat::Ply},
                        Case{"binary.stl", "binary-stl-named.obj", MeshFormat::Stl},
                        Case{"ascii.stl", "ascii-stl-named.ply", MeshFormat::Stl},
                        Case{"t.obj", "obj-without-extension", MeshFormat::Obj}}) {
    SCOPED_TRACE(c.misleading);
    const LoadedInput loaded = loadInput(copyAs(file(c.original), c.misleading), kEveryKind);
    ASSERT_EQ(loaded.kind(), InputKind::Mesh);
    const MeshInput& input = std::get<MeshInput>(loaded.value);
    EXPECT_EQ(input.format, c.format);
    // The reader of the format, on the correctly named file, is the reference.
    expectSameMesh(input.mesh, readMesh(file(c.original)));
    EXPECT_EQ(input.mesh.triangleCount(), 4u);
  }
}

TEST_F(InputFileTest, PointSetsAreRecognizedByContent) {
  const std::vector<Vector3d> points = {{0.1, -2.5, 3.0}, {1e-300, 0.3, 7.0}, {-0.0, 4.0, 1.0 / 3}};
  writePointSet(file("cloud.xyz"), points);
  const std::filesystem::path named = copyAs(file("cloud.xyz"), "cloud-named.obj");
  expectSamePoints(loadInputAs<PointSetInput>(named).points, points);
  // A comment first: the first line with data decides.
  write("commented.ply", "# x y z\n\n  # more\n1 2 3\n4 5 6 extra columns\n");
  expectSamePoints(loadInputAs<PointSetInput>(file("commented.ply")).points,
                   {Vector3d(1, 2, 3), Vector3d(4, 5, 6)});
}

TEST_F(InputFileTest, PlyIsAMeshWithFacesElseAPointSet) {
  TriangleMesh vertices = tetrahedron();
  vertices.triangles.clear();
  writeMesh(file("vertices.ply"), vertices, MeshWriteOptions{false});
  writeMesh(file("faces.ply"), tetrahedron());
  const std::filesystem::path cloud = copyAs(file("vertices.ply"), "vertices-named.xyz");
  std::vector<Vector3d> expected;
  for (const Eigen::Vector3f& p : vertices.positions) expected.push_back(p.cast<double>());

  // Both accepted: faces decide.
  EXPECT_EQ(loadInput(file("faces.ply"), kEveryKind).kind(), InputKind::Mesh);
  const LoadedInput points = loadInput(cloud, kEveryKind);
  ASSERT_EQ(points.kind(), InputKind::PointSet);
  expectSamePoints(std::get<PointSetInput>(points.value).points, expected);
  // Only points wanted: a mesh's vertices.
  expectSamePoints(loadInputAs<PointSetInput>(file("faces.ply")).points, expected);
  // Only meshes wanted: a mesh without faces.
  EXPECT_EQ(loadInputAs<MeshInput>(cloud).mesh.triangleCount(), 0u);
}

TEST_F(InputFileTest, JsonDocumentsAreToldApartByTheirType) {
  const BSplineCurve curve(KnotVector(2, {0, 0, 0, 0.5, 1, 1, 1}),
                           {{0, 0, 0}, {1, 2, 0}, {2, 2, 0}, {3, 0, 0}}, 2);
  writeCurveJson(file("curve.json"), curve);
  const BSplineSurface surface(KnotVector(1, {0, 0, 1, 1}), KnotVector(1, {0, 0, 1, 1}),
                               {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0.5}});
  writeSurfaceJson(file("surface.json"), surface);
  Polyline polyline;
  polyline.points = {{0, 0, 0}, {1, 0.5, 0}, {2, 0, 0}};
  polyline.dimension = 2;
  writePolyline(file("polyline.json"), polyline);
  write("slice.json",
        R"({"axis": "z", "offset": 0, "iso": 0, "plane_axes": ["x", "y"], "polylines": [)"
        R"({"closed": true, "points": [[0, 0], [1, 0], [0, 1]]},)"
        R"({"closed": false, "points": [[2, 2], [3, 3]]}]})");

  const BSplineCurve readCurve = loadInputAs<BSplineCurve>(copyAs(file("curve.json"), "c.txt"));
  expectSamePoints(readCurve.controlPoints(), curve.controlPoints());
  EXPECT_EQ(readCurve.dimension(), 2);
  const BSplineSurface readSurface =
      loadInputAs<BSplineSurface>(copyAs(file("surface.json"), "s.vdb"));
  EXPECT_EQ(readSurface.countU(), 2);
  EXPECT_TRUE(sameBits(readSurface.controlPoint(1, 1).z(), 0.5));
  const std::vector<Polyline> lines =
      loadInputAs<PolylinesInput>(copyAs(file("polyline.json"), "p.obj")).polylines;
  ASSERT_EQ(lines.size(), 1u);
  expectSamePoints(lines.front().points, polyline.points);
  const std::vector<Polyline> slice = loadInputAs<PolylinesInput>(file("slice.json")).polylines;
  ASSERT_EQ(slice.size(), 2u);
  EXPECT_TRUE(slice[0].closed);
  EXPECT_EQ(slice[1].points.size(), 2u);
  expectInputError([&] { onlyPolyline(slice, file("slice.json")); }, {"holds 2 polylines"});
}

TEST_F(InputFileTest, VdbIsAStoredFieldALevelSetOrItsGrids) {
  const openvdb::FloatGrid::Ptr sphere = sphereLevelSet();
  sphere->setName("surface");
  openvdb::DoubleGrid::Ptr density = openvdb::DoubleGrid::create(0.0);
  density->setName("density");
  density->tree().setValue(openvdb::Coord(1, 2, 3), 0.5);
  writeVdb(file("sphere.vdb"), {density, sphere});
  const std::filesystem::path levelSet = copyAs(file("sphere.vdb"), "sphere-named.json");

  // LevelSet: the float level set, or a double grid where the caller allows one.
  const LevelSetInput input = loadInputAs<LevelSetInput>(levelSet);
  ASSERT_EQ(input.grids.size(), 2u);
  EXPECT_EQ(input.grid->getName(), "surface");
  ASSERT_TRUE(input.floatGrid());
  EXPECT_EQ(input.floatGrid()->activeVoxelCount(), sphere->activeVoxelCount());
  LoadOptions named;
  named.gridName = "density";
  expectInputError([&] { loadInputAs<LevelSetInput>(levelSet, named); },
                   {"grid 'density'", "holds double values", "a float grid is needed"});
  named.gridTypes = ScalarGridTypes::FloatOrDouble;
  const LevelSetInput doubleInput = loadInputAs<LevelSetInput>(levelSet, named);
  EXPECT_EQ(doubleInput.grid->getName(), "density");
  EXPECT_FALSE(doubleInput.floatGrid());

  // VdbGrids: every grid, in file order.
  const std::vector<openvdb::GridBase::Ptr> grids = loadInputAs<VdbGridsInput>(levelSet).grids;
  ASSERT_EQ(grids.size(), 2u);
  EXPECT_EQ(grids[0]->getName(), "density");
  EXPECT_EQ(grids[1]->getName(), "surface");

  // Field from a level set: computed now, the same as fromLevelSet() on the grid.
  const FieldInput computed = loadInputAs<FieldInput>(levelSet);
  EXPECT_FALSE(computed.stored);
  expectSameAnswers(computed.field, ApproximantField::fromLevelSet(sphere));
  // With LevelSet also accepted, a plain level set stays a level set.
  EXPECT_EQ(loadInput(levelSet, {InputKind::Field, InputKind::LevelSet}).kind(),
            InputKind::LevelSet);

  // A stored field, whatever its name: read back, answering as readField() does.
  writeField(file("field.vdb"), computed.field);
  const std::filesystem::path stored = copyAs(file("field.vdb"), "field-named.obj");
  for (const InputKinds kinds :
       {InputKinds{InputKind::Field}, InputKinds{InputKind::Field, InputKind::LevelSet}}) {
    LoadedInput loaded = loadInput(stored, kinds);
    ASSERT_EQ(loaded.kind(), InputKind::Field);
    const FieldInput field = std::move(loaded).take<FieldInput>();
    EXPECT_TRUE(field.stored);
    expectSameAnswers(field.field, readField(file("field.vdb")));
  }
  // ... and its distance grid is the level set of callers that want one.
  EXPECT_EQ(loadInputAs<LevelSetInput>(stored).grid->getName(), "surface");
}

TEST_F(InputFileTest, TheExtensionDecidesWhereTheContentCannot) {
  // A truncated binary STL no longer has the size its header announces: the .stl extension
  // sends it to the STL reader, which says what is wrong.
  writeMesh(file("whole.stl"), tetrahedron());
  const std::string whole = test::readWholeFile(file("whole.stl"));
  write("cut.stl", whole.substr(0, whole.size() - 20));
  expectInputError([&] { loadInput(file("cut.stl"), kEveryKind); }, {"cut.stl"});
  // Only comments: the .xyz extension decides, and the point reader finds no points.
  write("comments.xyz", "# nothing here\n");
  expectInputError([&] { loadInput(file("comments.xyz"), kEveryKind); },
                   {"comments.xyz", "contains no points"});
  // A text file with a .vdb extension is reported by the .vdb reader.
  write("text.vdb", "hello world\n");
  expectInputError([&] { loadInput(file("text.vdb"), {InputKind::LevelSet}); },
                   {"text.vdb", "not a .vdb file"});
}

TEST_F(InputFileTest, ErrorsNameTheFileAndWhatWasExpected) {
  LoadOptions options;
  options.purpose = "the target of the test";
  const InputKinds curves = {InputKind::Curve, InputKind::Polylines};

  expectInputError([&] { loadInput(file("absent.json"), curves, options); },
                   {"absent.json", "does not exist"});
  expectInputError([&] { loadInput(scratch_, curves, options); }, {"is a directory"});
  write("empty.json", "");
  expectInputError([&] { loadInput(file("empty.json"), curves, options); },
                   {"empty.json", "is empty",
                    "the target of the test must be a B-spline curve (.json) or a polyline "
                    "(.json)"});
  write("notes.dat", "some words, not a format\n");
  expectInputError(
      [&] { loadInput(file("notes.dat"), curves, options); },
      {"cannot tell what", "notes.dat", "extension '.dat'", "the target of the test must be"});
  write("noise", std::string("\x01\x02\x03\x04\xff\xfe", 6));
  expectInputError([&] { loadInput(file("noise"), curves, options); },
                   {"cannot tell what", "it has no extension"});

  // Truncated files: the reader of the recognised format reports it, naming the file.
  write("cut.json", R"({"type": "bspline_curve", "version": 1, "knots": [0, 0,)");
  expectInputError([&] { loadInput(file("cut.json"), curves, options); },
                   {"cut.json", "invalid JSON at byte"});
  writeMesh(file("whole.ply"), tetrahedron());
  const std::string ply = test::readWholeFile(file("whole.ply"));
  write("cut.ply", ply.substr(0, ply.size() - 7));
  expectInputError([&] { loadInput(file("cut.ply"), {InputKind::Mesh}); }, {"cut.ply"});
  writeVdb(file("whole.vdb"), {sphereLevelSet()});
  const std::string vdb = test::readWholeFile(file("whole.vdb"));
  write("cut.vdb", vdb.substr(0, vdb.size() / 2));
  expectInputError([&] { loadInput(file("cut.vdb"), {InputKind::LevelSet}); },
                   {"cut.vdb", "truncated"});

  // JSON that is not one of d2vdb's documents.
  write("other.json", R"({"type": "feature_collection"})");
  expectInputError([&] { loadInput(file("other.json"), curves, options); },
                   {"other.json", "\"feature_collection\"", "\"bspline_curve\""});
  write("untyped.json", "  { }");
  expectInputError([&] { loadInput(file("untyped.json"), curves, options); },
                   {"untyped.json", "has no \"type\""});

  // A kind the caller does not accept.
  write("surface.json",
        surfaceToJson(BSplineSurface(KnotVector(1, {0, 0, 1, 1}), KnotVector(1, {0, 0, 1, 1}),
                                     {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 1}})));
  expectInputError([&] { loadInput(file("surface.json"), curves, options); },
                   {"'" + file("surface.json").string() + "' is a B-spline surface (.json)",
                    "the target of the test must be a B-spline curve (.json) or a polyline"});
  expectInputError([&] { loadInputAs<BSplineCurve>(file("whole.vdb")); },
                   {"is a .vdb grid file", "must be a B-spline curve (.json)"});
  expectInputError([&] { loadInputAs<FieldInput>(file("whole.ply")); },
                   {"is a PLY file", "must be an approximant field or a level set (.vdb)"});
  writeMesh(file("whole.stl"), tetrahedron());
  expectInputError([&] { loadInput(file("whole.stl"), {InputKind::PointSet}); },
                   {"is a triangle mesh (STL)", "must be a point set"});

  // Taking a value as a kind it was not loaded as is a programming error.
  LoadedInput surface = loadInput(file("surface.json"), kEveryKind);
  EXPECT_THROW(std::move(surface).take<BSplineCurve>(), RuntimeFailure);
  EXPECT_THROW(loadInput(file("surface.json"), {}), RuntimeFailure);
}

}  // namespace
}  // namespace d2vdb
