// Support functions of files: support-function files recognised by loadInput() by their content
// whatever their extension, what loadSupportInput() makes of each kind of input, fitAndCheck()
// against the ellipsoid's exact support function h(n) = |A n|, and the patches of a torus level
// set. References: the ellipsoid's closed form, the sphere's distances, and the documents written.
#include "d2vdb/io/SupportInput.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/Icosphere.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/io/SupportFunctionJson.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/mesh/MeshIO.h"
#include "io/IoTestSupport.h"

namespace d2vdb {
namespace {

using Eigen::Vector3d;
using test::expectInputError;

constexpr double kA = 2.0, kB = 1.5, kC = 1.0;  // semi-axes of the test ellipsoid

// h(n) = |A n| of the ellipsoid x^T A^-2 x = 1, A = diag(a, b, c).
double ellipsoidSupport(const Vector3d& n) {
  return Vector3d(kA * n.x(), kB * n.y(), kC * n.z()).norm();
}

// The icosphere (`levels` subdivisions) scaled to the ellipsoid, with its exact unit normals
// (x / a^2, y / b^2, z / c^2) normalised, unless `withNormals` is false.
TriangleMesh ellipsoidMesh(int levels, bool withNormals = true) {
  const test::UnitIcosphere sphere = test::unitIcosphere(levels);
  TriangleMesh mesh;
  for (const Vector3d& u : sphere.positions) {
    mesh.positions.push_back(Vector3d(kA * u.x(), kB * u.y(), kC * u.z()).cast<float>());
    if (withNormals) {
      mesh.normals.push_back(
          Vector3d(u.x() / kA, u.y() / kB, u.z() / kC).normalized().cast<float>());
    }
  }
  mesh.triangles = sphere.triangles;
  return mesh;
}

// A support function of degree 2 whose every coefficient has a distinct value.
SupportFunctionDocument smallDocument() {
  Eigen::VectorXd coefficients(9);
  coefficients << 3.5, 0.01, -0.02, 0.03, 0.004, -0.005, 0.006, 0.007, -0.008;
  SupportFunctionDocument document;
  document.function = SupportFunction(2, coefficients);
  document.fit = SupportFitRecord{"ellipsoid.obj", 100, 1e-10, 1e-4, 2e-4};
  return document;
}

class SupportInputTest : public test::ScratchDirectoryTest {};

TEST_F(SupportInputTest, LoadInputRecognizesSupportFunctionFilesByContent) {
  EXPECT_STREQ(inputKindName(InputKind::SupportFunction), "support function");
  EXPECT_EQ(describeInputKind(InputKind::SupportFunction), "a support function (.json)");
  const SupportFunctionDocument written = smallDocument();
  const std::string text = supportFunctionToJson(written);
  for (const std::string name : {"h.json", "h.obj", "h.vdb", "h"}) {
    const std::filesystem::path path = write(name, text);
    const LoadedInput loaded = loadInput(path, {InputKind::Mesh, InputKind::SupportFunction});
    ASSERT_EQ(loaded.kind(), InputKind::SupportFunction) << name;
    const auto& read = std::get<SupportFunctionDocument>(loaded.value);
    ASSERT_EQ(read.function.degree(), 2);
    for (int j = 0; j < 9; ++j) {
      EXPECT_TRUE(
          test::sameBits(read.function.coefficients()[j], written.function.coefficients()[j]))
          << name << ", coefficient " << j;
    }
    ASSERT_TRUE(read.fit.has_value());
    EXPECT_EQ(read.fit->source, "ellipsoid.obj");
    EXPECT_FALSE(read.patch.has_value());
  }
  EXPECT_EQ(loadInputAs<SupportFunctionDocument>(file("h")).function.degree(), 2);
}

TEST_F(SupportInputTest, LoadInputNamesSupportFunctionsInItsErrors) {
  const std::filesystem::path path = write("h.json", supportFunctionToJson(smallDocument()));
  LoadOptions options;
  options.purpose = "the target of the test";
  expectInputError(
      [&] {
        loadInput(path, {InputKind::Curve, InputKind::Polylines}, options);
      },
      {"'" + path.string() +
       "' is a support function (.json); the target of the "
       "test must be a B-spline curve (.json) or a polyline "
       "(.json)"});
  // The messages of the other kinds keep their form, with the new kind among the accepted ones.
  const std::filesystem::path curve = write(
      "c.json", curveToJson(BSplineCurve(KnotVector(1, {0, 0, 1, 1}), {{0, 0, 0}, {1, 0, 0}})));
  expectInputError(
      [&] {
        loadInput(curve, {InputKind::Mesh, InputKind::SupportFunction}, options);
      },
      {"'" + curve.string() +
       "' is a B-spline curve (.json); the target of the test "
       "must be a triangle mesh (.obj, .ply, .stl) or a "
       "support function (.json)"});
  // The JSON types d2vdb reads include the support function's.
  write("other.json", R"({"type": "feature_collection"})");
  expectInputError([&] { loadInput(file("other.json"), {InputKind::SupportFunction}); },
                   {"\"feature_collection\"", "\"support_function\""});
  // A malformed document: the support-function reader's message, with the field.
  write("bad.obj",
        R"({"type": "support_function", "version": 1, "basis": "real_spherical_harmonics", )"
        R"("degree": 1, "coefficients": [1, 2], "domain": {"kind": "sphere"}})");
  expectInputError([&] { loadInput(file("bad.obj"), {InputKind::SupportFunction}); },
                   {"support-function file '" + file("bad.obj").string() +
                    "', field 'coefficients': has 2 numbers, but degree 1 needs 4"});
}

TEST_F(SupportInputTest, LoadSupportInputTellsEveryKindApart) {
  EXPECT_STREQ(supportInputKindName(SupportInputKind::Mesh), "mesh");
  EXPECT_STREQ(supportInputKindName(SupportInputKind::MeshPatch), "mesh patch");
  EXPECT_STREQ(supportInputKindName(SupportInputKind::Points), "points");
  EXPECT_STREQ(supportInputKindName(SupportInputKind::LevelSet), "level set");
  EXPECT_STREQ(supportInputKindName(SupportInputKind::Field), "field");
  EXPECT_STREQ(supportInputKindName(SupportInputKind::SupportFunction), "support function");

  // A closed mesh with normals: every vertex a sample, its Gauss image all convex.
  const TriangleMesh closed = ellipsoidMesh(2);
  writeMesh(file("e.obj"), closed);
  const SupportInput mesh = loadSupportInput(file("e.obj"));
  EXPECT_EQ(mesh.kind, SupportInputKind::Mesh);
  EXPECT_EQ(mesh.samples.points.size(), closed.positions.size());
  ASSERT_TRUE(mesh.gaussImage.has_value());
  EXPECT_EQ(mesh.gaussImage->preservingTriangles, closed.triangles.size());
  EXPECT_FALSE(mesh.patch.has_value());
  EXPECT_TRUE(mesh.warnings.empty());
  // Without normals: the same kind, with a warning.
  writeMesh(file("flat.obj"), ellipsoidMesh(2, false));
  const SupportInput flat = loadSupportInput(file("flat.obj"));
  EXPECT_EQ(flat.kind, SupportInputKind::Mesh);
  ASSERT_EQ(flat.warnings.size(), 1u);
  EXPECT_NE(flat.warnings[0].find("has no vertex normals"), std::string::npos);

  // An open mesh (the triangles above z = 0.3): fitted over its Gauss image.
  TriangleMesh cap = closed;
  cap.triangles.clear();
  for (const auto& t : closed.triangles) {
    if (closed.positions[t[0]].z() > 0.3f && closed.positions[t[1]].z() > 0.3f &&
        closed.positions[t[2]].z() > 0.3f) {
      cap.triangles.push_back(t);
    }
  }
  writeMesh(file("cap.ply"), cap);
  const SupportInput patch = loadSupportInput(file("cap.ply"));
  EXPECT_EQ(patch.kind, SupportInputKind::MeshPatch);
  ASSERT_TRUE(patch.patch.has_value());
  EXPECT_EQ(patch.patch->triangles.size(), cap.triangles.size());

  // A PLY without faces: points with their normals.
  write("points.ply",
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
        "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
        "end_header\n1 0 0 1 0 0\n0 0 2 0 0 1\n");
  const SupportInput points = loadSupportInput(file("points.ply"));
  EXPECT_EQ(points.kind, SupportInputKind::Points);
  ASSERT_EQ(points.samples.points.size(), 2u);
  EXPECT_EQ(points.samples.normals[1], Vector3d::UnitZ());

  // A support-function file, whatever its name.
  write("h.txt", supportFunctionToJson(smallDocument()));
  const SupportInput document = loadSupportInput(file("h.txt"));
  EXPECT_EQ(document.kind, SupportInputKind::SupportFunction);
  ASSERT_TRUE(document.document.has_value());
  EXPECT_TRUE(document.samples.points.empty());

  // A level set: band footpoints on the sphere, normals radial.
  const Vector3d center(0.1, -0.2, 0.3);
  writeVdb(file("sphere.vdb"), {primitiveLevelSet(Sphere(center, 1.0), {0.05, 3.0})});
  const SupportInput levelSet = loadSupportInput(file("sphere.vdb"));
  EXPECT_EQ(levelSet.kind, SupportInputKind::LevelSet);
  ASSERT_GT(levelSet.samples.points.size(), 1000u);
  for (std::size_t i = 0; i < levelSet.samples.points.size(); ++i) {
    const Vector3d radial = levelSet.samples.points[i] - center;
    ASSERT_NEAR(radial.norm(), 1.0, 5e-3) << "sample " << i;
    ASSERT_GT(radial.normalized().dot(levelSet.samples.normals[i]), 0.999) << "sample " << i;
  }

  // Anything else: the accepted kinds, support functions among them.
  write("c.json", curveToJson(BSplineCurve(KnotVector(1, {0, 0, 1, 1}), {{0, 0, 0}, {1, 0, 0}})));
  expectInputError([&] { loadSupportInput(file("c.json")); },
                   {"is a B-spline curve (.json); a support function's input",
                    "must be a triangle mesh (.obj, .ply, .stl), an approximant field or a level "
                    "set (.vdb) or a support function (.json)"});
}

TEST_F(SupportInputTest, FitAndCheckMatchesTheEllipsoid) {
  writeMesh(file("ellipsoid.obj"), ellipsoidMesh(5));
  const SupportInput input = loadSupportInput(file("ellipsoid.obj"));
  const CheckedSupport support = fitAndCheck(input, file("ellipsoid.obj").string(), {12});
  ASSERT_TRUE(support.fit.has_value());
  ASSERT_TRUE(support.document.fit.has_value());
  EXPECT_EQ(support.document.fit->source, "ellipsoid.obj");
  EXPECT_EQ(support.document.fit->samples, input.samples.points.size());
  EXPECT_EQ(support.document.fit->regularization, kDefaultSupportRegularization);
  EXPECT_TRUE(support.warnings.empty());
  double worst = 0.0;
  for (int i = 0; i < 500; ++i) {
    const double t = 0.37 * i, s = std::asin(2.0 * ((i * 0.618034) - std::floor(i * 0.618034)) - 1);
    const Vector3d n(std::cos(t) * std::cos(s), std::sin(t) * std::cos(s), std::sin(s));
    worst = std::max(worst,
                     std::abs(support.document.function.evaluate(n).value - ellipsoidSupport(n)));
  }
  EXPECT_LT(worst, 2e-3);
  ASSERT_TRUE(support.validity.regular());
  // The smallest principal radius, c^2 / a at the ends of the long axis.
  EXPECT_NEAR(support.validity.minRadius, kC * kC / kA, 0.02);

  // A support-function file is taken as it is: no fit, the same coefficients.
  writeSupportFunctionJson(file("e-sf.json"), support.document);
  const CheckedSupport read = fitAndCheck(loadSupportInput(file("e-sf.json")), "e-sf.json");
  EXPECT_FALSE(read.fit.has_value());
  EXPECT_EQ(read.document.function.coefficients(), support.document.function.coefficients());
  EXPECT_EQ(read.validity.minRadius, support.validity.minRadius);
}

TEST_F(SupportInputTest, FitAndCheckRefusesASingularFitUnlessAllowed) {
  // A closed non-convex surface (a torus) has no support function over the sphere.
  writeVdb(file("torus.vdb"), {primitiveLevelSet(Torus(Vector3d::Zero(), 1.0, 0.35), {0.05, 3.0})});
  const SupportInput input = loadSupportInput(file("torus.vdb"));
  EXPECT_EQ(input.kind, SupportInputKind::LevelSet);
  expectInputError([&] { fitAndCheck(input, "torus.vdb", {8}); },
                   {"'torus.vdb': the support function is", "--allow-singular"});
  const CheckedSupport kept = fitAndCheck(input, "torus.vdb", {8, -1.0, true});
  ASSERT_FALSE(kept.warnings.empty());
  EXPECT_NE(kept.warnings.back().find("(kept: --allow-singular)"), std::string::npos);
  // analyzeSupportDocument() reports on such a function without refusing it.
  const CheckedSupport analyzed = analyzeSupportDocument(kept.document);
  EXPECT_EQ(analyzed.validity.regular(), kept.validity.regular());
  EXPECT_EQ(analyzed.validity.minRadius, kept.validity.minRadius);
  EXPECT_TRUE(analyzed.warnings.empty());
}

TEST_F(SupportInputTest, PatchesOfATorusLevelSet) {
  const double major = 1.0, minor = 0.35;
  writeVdb(file("torus.vdb"),
           {primitiveLevelSet(Torus(Vector3d::Zero(), major, minor), {0.04, 3.0})});
  const PatchSurface surface = loadPatchSurface(file("torus.vdb"));
  EXPECT_EQ(surface.kind, InputKind::LevelSet);
  ASSERT_GT(surface.mesh.triangles.size(), 1000u);
  EXPECT_TRUE(surface.mesh.hasNormals());
  SupportPatchOptions options;
  options.degree = 8;
  const PatchedSupport patched = fitPatches(surface, options, file("torus.vdb").string());
  EXPECT_EQ(patched.kind, InputKind::LevelSet);
  ASSERT_GE(patched.set.patches.size(), 2u);
  bool convex = false, saddle = false;
  for (const SupportPatch& p : patched.set.patches) {
    convex = convex || p.signs == RadiusSigns::Convex;
    saddle = saddle || p.signs == RadiusSigns::Saddle;
  }
  EXPECT_TRUE(convex);  // the outer half
  EXPECT_TRUE(saddle);  // the inner half
  // The band along the parabolic circles is in no patch, and the warning says how much.
  ASSERT_FALSE(patched.warnings.empty());
  EXPECT_NE(patched.warnings.back().find("% of the triangles are in no patch"), std::string::npos);
  // Every patch stays regular up to the torus's own limit R - r outward.
  EXPECT_LT(patched.set.safeOffsetMax(), major - minor + 0.02);

  const std::vector<SupportFunctionDocument> documents =
      supportPatchDocuments(patched.set, file("torus.vdb").string());
  ASSERT_EQ(documents.size(), patched.set.patches.size());
  for (std::size_t i = 0; i < documents.size(); ++i) {
    ASSERT_TRUE(documents[i].patch.has_value());
    EXPECT_EQ(documents[i].patch->triangles,
              patched.set.patches[i].gaussImage.gaussImage.triangles);
    ASSERT_TRUE(documents[i].fit.has_value());
    EXPECT_EQ(documents[i].fit->source, "torus.vdb");
    EXPECT_EQ(documents[i].fit->samples, patched.set.patches[i].fit.samples);
  }
}

TEST_F(SupportInputTest, PatchSurfacesNeedConnectivity) {
  write("points.ply",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n1 0 0\n");
  expectInputError([&] { loadPatchSurface(file("points.ply")); },
                   {"has no triangles: splitting into patches needs the surface's connectivity"});
  write("h.json", supportFunctionToJson(smallDocument()));
  expectInputError([&] { loadPatchSurface(file("h.json")); },
                   {"is a support function (.json); the input of --patches (a mesh with triangles "
                    "or a level set) must be a triangle mesh (.obj, .ply, .stl) or a level set "
                    "(.vdb)"});
  // A mesh without normals is split with area-weighted ones, with a warning.
  writeMesh(file("flat.obj"), ellipsoidMesh(1, false));
  const PatchSurface flat = loadPatchSurface(file("flat.obj"));
  EXPECT_EQ(flat.kind, InputKind::Mesh);
  ASSERT_EQ(flat.warnings.size(), 1u);
  EXPECT_NE(flat.warnings[0].find("has no vertex normals"), std::string::npos);
}

}  // namespace
}  // namespace d2vdb
