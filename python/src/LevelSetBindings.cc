// d2vdb.LevelSet: narrow-band distance grids from meshes and primitives, meshed by the engine's
// marching cubes, written as .vdb, and handed to and from pyopenvdb without a copy.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <openvdb/tools/Interpolation.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "Arrays.h"
#include "Bindings.h"
#include "LongCall.h"
#include "OpenVdbBridge.h"
#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/VdbFile.h"

namespace d2vdb::python {

namespace {

constexpr const char* kThreadsDoc =
    "threads: TBB threads (0: all cores); results do not depend on it.";

LevelSet levelSetFromMesh(const TriangleMesh& mesh, double voxelSize, int resolution,
                          double halfWidth, bool signedDistance, bool exactSigns,
                          std::uint64_t maxVoxels, int threads, const py::object& progress) {
  LevelSetOptions options;
  options.voxelSize = voxelSize;
  options.resolution = voxelSize > 0 ? 0 : resolution;
  options.halfWidth = halfWidth;
  options.unsignedDistance = !signedDistance;
  options.exactSigns = exactSigns;
  options.maxActiveVoxels = maxVoxels;
  auto result = runLong<LevelSetResult>(progress, threads, [&](const ProgressCallback& report) {
    return meshToLevelSet(mesh, options, report);
  });
  LevelSet levelSet;
  levelSet.grid = result.grid;
  levelSet.halfWidth = halfWidth;
  levelSet.meshReport = result.meshReport;
  if (signedDistance) levelSet.signs = result.signs;
  levelSet.warnings = std::move(result.warnings);
  return levelSet;
}

LevelSet levelSetOfShape(const AnalyticShape& shape, double voxelSize, int resolution,
                         double halfWidth, std::uint64_t maxVoxels, int threads) {
  PrimitiveLevelSetOptions options;
  options.voxelSize =
      voxelSizeForBox(shape.bounds().sizes().maxCoeff(), voxelSize, resolution, "shape");
  options.halfWidth = halfWidth;
  options.maxActiveVoxels = maxVoxels;
  LevelSet levelSet;
  levelSet.halfWidth = halfWidth;
  runWithoutGil(threads, [&] { levelSet.grid = primitiveLevelSet(shape, options); });
  return levelSet;
}

const openvdb::FloatGrid& gridOf(const LevelSet& levelSet) {
  if (!levelSet.grid) throw InputError("the level set holds no grid");
  return *levelSet.grid;
}

py::dict signReportDict(const SignReport& signs) {
  py::dict report;
  report["method"] = signMethodName(signs.method);
  report["corrected_voxels"] = signs.correctedVoxels;
  report["winding_number_queries"] = signs.windingNumberQueries;
  report["reoriented_triangles"] = signs.reorientedTriangles;
  report["watertight"] = signs.watertight;
  report["holes_closed"] = signs.holesClosed;
  report["self_intersecting"] = signs.selfIntersecting;
  report["pockets_filled"] = signs.pocketsFilled;
  report["pocket_voxels"] = signs.pocketVoxels;
  report["hole_voxels"] = signs.holeVoxels;
  return report;
}

// The interpolated grid values at the points (trilinear, OpenVDB's BoxSampler), in parallel.
py::array_t<double> valuesAt(const LevelSet& levelSet, const py::handle& pointsArray, int threads) {
  const openvdb::FloatGrid& grid = gridOf(levelSet);
  const std::vector<Eigen::Vector3d> points = pointsFromArray(pointsArray, "points");
  std::vector<double> values(points.size());
  runWithoutGil(threads, [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        const openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor,
                                                          openvdb::tools::BoxSampler>
                            sampler(grid.getConstAccessor(), grid.transform());
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          const Eigen::Vector3d& p = points[i];
                          values[i] = sampler.wsSample(openvdb::Vec3d(p.x(), p.y(), p.z()));
                        }
                      });
  });
  return arrayOwning(std::move(values), {static_cast<py::ssize_t>(points.size())});
}

/// The static constructors: from meshes, primitives and pyopenvdb grids.
void addFactories(py::class_<LevelSet>& levelSet) {
  levelSet
      .def_static(
          "from_mesh",
          [](const TriangleMesh& mesh, double voxelSize, int resolution, double halfWidth,
             bool signedDistance, bool exactSigns, std::uint64_t maxVoxels, int threads,
             const py::object& progress) {
            return levelSetFromMesh(mesh, voxelSize, resolution, halfWidth, signedDistance,
                                    exactSigns, maxVoxels, threads, progress);
          },
          py::arg("mesh"), py::kw_only(), py::arg("voxel_size") = 0.0,
          py::arg("resolution") = kDefaultResolution, py::arg("half_width") = 3.0,
          py::arg("signed") = true, py::arg("exact_signs") = true,
          py::arg("max_voxels") = kDefaultMaxActiveVoxels, py::arg("threads") = 0,
          py::arg("progress") = py::none(),
          (std::string("The level set of a triangle mesh, as `d2vdb mesh2sdf` makes it. "
                       "voxel_size: world units (0: the longest bounding-box side over "
                       "resolution); half_width: band half-width in voxels; signed=False: "
                       "unsigned distance (open surfaces); exact_signs=False keeps OpenVDB's "
                       "signs unchecked (faster, can be wrong). ") +
           kThreadsDoc +
           " progress: None or callable(stage, fraction). Raises InputError for empty or "
           "degenerate meshes and for bands over max_voxels (before allocating).")
              .c_str())
      .def_static(
          "sphere",
          [](const py::object& center, double radius, double voxelSize, int resolution,
             double halfWidth, std::uint64_t maxVoxels, int threads) {
            return levelSetOfShape(Sphere(vector3FromObject(center, "center"), radius), voxelSize,
                                   resolution, halfWidth, maxVoxels, threads);
          },
          py::arg("center"), py::arg("radius"), py::kw_only(), py::arg("voxel_size") = 0.0,
          py::arg("resolution") = 100, py::arg("half_width") = 3.0,
          py::arg("max_voxels") = kDefaultMaxActiveVoxels, py::arg("threads") = 0,
          "The level set of a sphere with exact distances at every band voxel (as `d2vdb "
          "primitive sphere`): voxel_size in world units, or 0 for the bounding box's longest "
          "side over resolution.")
      .def_static(
          "box",
          [](const py::object& min, const py::object& max, double voxelSize, int resolution,
             double halfWidth, std::uint64_t maxVoxels, int threads) {
            return levelSetOfShape(
                Box(vector3FromObject(min, "min"), vector3FromObject(max, "max")), voxelSize,
                resolution, halfWidth, maxVoxels, threads);
          },
          py::arg("min"), py::arg("max"), py::kw_only(), py::arg("voxel_size") = 0.0,
          py::arg("resolution") = 100, py::arg("half_width") = 3.0,
          py::arg("max_voxels") = kDefaultMaxActiveVoxels, py::arg("threads") = 0,
          "The level set of the axis-aligned box [min, max] (as `d2vdb primitive box`).")
      .def_static(
          "torus",
          [](const py::object& center, double major, double minor, double voxelSize, int resolution,
             double halfWidth, std::uint64_t maxVoxels, int threads) {
            return levelSetOfShape(Torus(vector3FromObject(center, "center"), major, minor),
                                   voxelSize, resolution, halfWidth, maxVoxels, threads);
          },
          py::arg("center"), py::arg("major_radius"), py::arg("minor_radius"), py::kw_only(),
          py::arg("voxel_size") = 0.0, py::arg("resolution") = 100, py::arg("half_width") = 3.0,
          py::arg("max_voxels") = kDefaultMaxActiveVoxels, py::arg("threads") = 0,
          "The level set of a ring torus about the z axis through center (as `d2vdb primitive "
          "torus`).")
      .def_static(
          "cylinder",
          [](const py::object& center, double radius, double height, double voxelSize,
             int resolution, double halfWidth, std::uint64_t maxVoxels, int threads) {
            return levelSetOfShape(
                CappedCylinder(vector3FromObject(center, "center"), radius, height), voxelSize,
                resolution, halfWidth, maxVoxels, threads);
          },
          py::arg("center"), py::arg("radius"), py::arg("height"), py::kw_only(),
          py::arg("voxel_size") = 0.0, py::arg("resolution") = 100, py::arg("half_width") = 3.0,
          py::arg("max_voxels") = kDefaultMaxActiveVoxels, py::arg("threads") = 0,
          "The level set of a capped cylinder along z (as `d2vdb primitive cylinder`).")
      .def_static(
          "from_openvdb",
          [](const py::object& grid) {
            LevelSet levelSet;
            levelSet.grid = fromPyopenvdb<openvdb::FloatGrid>(grid);
            if (!levelSet.grid) {
              throw InputError("from_openvdb() takes a pyopenvdb.FloatGrid; got a " +
                               std::string(py::str(py::type::of(grid).attr("__name__"))));
            }
            return levelSet;
          },
          py::arg("grid"),
          "The level set of a pyopenvdb.FloatGrid, sharing the grid (no copy): changes made "
          "through pyopenvdb are seen here.");
}

/// Meshing, sampling, writing and the hand-off to pyopenvdb.
void addOperations(py::class_<LevelSet>& levelSet) {
  levelSet
      .def(
          "to_openvdb", [](const LevelSet& levelSet) { return toPyopenvdb(levelSet.grid); },
          "The same grid as a pyopenvdb.FloatGrid (no copy, no file): both sides see each "
          "other's changes.")
      .def(
          "to_mesh",
          [](const LevelSet& levelSet, double isoValue, bool normals, int threads,
             const py::object& progress) {
            IsoSurfaceOptions options;
            options.isoValue = isoValue;
            options.computeNormals = normals;
            const openvdb::FloatGrid& grid = gridOf(levelSet);
            return std::make_shared<TriangleMesh>(
                runLong<TriangleMesh>(progress, threads, [&](const ProgressCallback& report) {
                  return extractIsoSurface(grid, options, report);
                }));
          },
          py::arg("isovalue") = 0.0, py::kw_only(), py::arg("normals") = true,
          py::arg("threads") = 0, py::arg("progress") = py::none(),
          "The iso-surface where the grid's trilinear interpolant equals isovalue (world units: "
          "+r is the outward offset by r), by the engine's marching cubes as `d2vdb mesh` "
          "extracts it: closed, manifold, oriented outward, with unit normals unless "
          "normals=False. Raises InputError when |isovalue| exceeds what the band represents.")
      .def("values", &valuesAt, py::arg("points"), py::kw_only(), py::arg("threads") = 0,
           "The grid's trilinear interpolant at (N, 3) world points (N,) float64; beyond the "
           "band, the background value (+-half-width in world units).")
      .def(
          "save",
          [](const LevelSet& levelSet, const std::filesystem::path& path, bool compression,
             bool halfFloat, const std::string& source) {
            VdbWriteOptions options;
            options.blosc = compression;
            options.halfFloat = halfFloat;
            options.source = source;
            options.halfWidth = levelSet.halfWidth;
            const openvdb::GridBase::Ptr grid = levelSet.grid;
            gridOf(levelSet);
            const py::gil_scoped_release release;
            writeVdb(path, {grid}, options);
          },
          py::arg("path"), py::kw_only(), py::arg("compression") = true,
          py::arg("half_float") = false, py::arg("source") = "",
          "Writes the grid to a .vdb file (Blosc-compressed unless compression=False; 16-bit "
          "floats with half_float=True), atomically: a failure leaves an existing file "
          "untouched.");
}

/// Sizes, the grid's kind and name, and how from_mesh() made it.
void addProperties(py::class_<LevelSet>& levelSet) {
  levelSet
      .def_property_readonly(
          "voxel_size", [](const LevelSet& levelSet) { return gridOf(levelSet).voxelSize()[0]; },
          "Voxel edge length, world units.")
      .def_property_readonly(
          "half_width",
          [](const LevelSet& levelSet) {
            const openvdb::FloatGrid& grid = gridOf(levelSet);
            return levelSet.halfWidth > 0 ? levelSet.halfWidth
                                          : grid.background() / grid.voxelSize()[0];
          },
          "Band half-width in voxels.")
      .def_property_readonly(
          "active_voxel_count",
          [](const LevelSet& levelSet) { return gridOf(levelSet).activeVoxelCount(); })
      .def_property_readonly(
          "signed",
          [](const LevelSet& levelSet) {
            return gridOf(levelSet).getGridClass() == openvdb::GRID_LEVEL_SET;
          },
          "True for a signed level set (d < 0 inside), False for unsigned distance.")
      .def_property_readonly("name",
                             [](const LevelSet& levelSet) { return gridOf(levelSet).getName(); })
      .def_property_readonly(
          "bounding_box",
          [](const LevelSet& levelSet) -> py::object {
            const openvdb::FloatGrid& grid = gridOf(levelSet);
            const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
            if (box.empty()) return py::none();
            const openvdb::Vec3d min = grid.indexToWorld(box.min());
            const openvdb::Vec3d max = grid.indexToWorld(box.max());
            return boxTuple({min.x(), min.y(), min.z()}, {max.x(), max.y(), max.z()});
          },
          "World-space box of the active voxel centres, or None without active voxels.")
      .def_property_readonly(
          "mesh_report", [](const LevelSet& levelSet) { return levelSet.meshReport; },
          "from_mesh(): the input mesh's MeshReport; otherwise None.")
      .def_property_readonly(
          "signs",
          [](const LevelSet& levelSet) -> py::object {
            if (!levelSet.signs) return py::none();
            return signReportDict(*levelSet.signs);
          },
          "from_mesh() with signed=True: how inside and outside were decided (dict); otherwise "
          "None.")
      .def_readonly("warnings", &LevelSet::warnings, "One sentence each, e.g. holes found.")
      .def("__repr__", [](const LevelSet& levelSet) {
        if (!levelSet.grid) return std::string("<d2vdb.LevelSet (empty)>");
        return "<d2vdb.LevelSet '" + levelSet.grid->getName() + "' " +
               std::to_string(levelSet.grid->activeVoxelCount()) + " active voxels, voxel size " +
               std::to_string(levelSet.grid->voxelSize()[0]) + ">";
      });
}

}  // namespace

void bindLevelSet(py::module_& module) {
  py::class_<LevelSet> levelSet(
      module, "LevelSet",
      "A narrow-band distance grid (an OpenVDB FloatGrid): signed (class level set, d < 0 "
      "inside) or unsigned, in world units, voxel (i, j, k) centred at (i, j, k) * voxel_size. "
      "The grid is shared, never copied: to_openvdb() gives pyopenvdb the same grid.");
  addFactories(levelSet);
  addOperations(levelSet);
  addProperties(levelSet);
}

}  // namespace d2vdb::python
