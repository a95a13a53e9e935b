// d2vdb.Field: the squared-distance approximant field of any target, its batch queries as numpy
// arrays (the same answers as `d2vdb query`), its SDM forms, and its .vdb files.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

#include "Arrays.h"
#include "Bindings.h"
#include "LongCall.h"
#include "OpenVdbBridge.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/Approximant.h"
#include "d2vdb/io/FieldFile.h"
#include "d2vdb/io/FieldFromInput.h"
#include "d2vdb/io/FieldGrids.h"
#include "d2vdb/io/FieldQuery.h"

namespace d2vdb::python {

namespace {

// Blocks of queries per task, as answerAll() (io/FieldQuery.cc): each keeps its accessor's leaf
// cache warm over consecutive points.
constexpr std::size_t kQueryBlock = 256;

const ApproximantField& fieldOf(const Field& field) {
  if (!field.field) throw InputError("the field holds nothing");
  return *field.field;
}

Field buildField(const py::object& target, double voxelSize, int resolution, double halfWidth,
                 double padding, const std::optional<std::string>& smooth, std::uint64_t maxVoxels,
                 int threads, const py::object& progress) {
  FieldBuildOptions options;
  options.voxelSize = voxelSize;
  options.resolution = resolution;
  options.halfWidth = halfWidth;
  options.field.domainPadding = padding;
  options.field.maxActiveVoxels = maxVoxels;
  if (smooth) {
    if (*smooth == "loop") {
      options.smooth = SmoothSurfaceSource::LoopLimit;
    } else if (*smooth == "pn") {
      options.smooth = SmoothSurfaceSource::PnTriangles;
    } else {
      throw InputError("smooth must be None, 'loop' or 'pn'; got '" + *smooth + "'");
    }
  }
  if (py::isinstance<py::str>(target)) {
    throw InputError(
        "Field() takes a Mesh, LevelSet, PointSet, Curve or (N, 3) points; to "
        "build the field of a file, pass d2vdb.load(path)");
  }
  // Converting the target needs the GIL; building it does not.
  openvdb::FloatGrid::Ptr levelSet;
  std::optional<LoadedInput> input;
  if (py::isinstance<LevelSet>(target)) {
    levelSet = target.cast<const LevelSet&>().grid;
    if (!levelSet) throw InputError("the level set holds no grid");
    if (options.smooth) {
      throw InputError("smooth= takes a Mesh; a level set has no smooth surface of its own");
    }
  } else {
    input = inputOf(target, "python");
  }
  auto built = runLong<BuiltField>(progress, threads, [&](const ProgressCallback& report) {
    FieldBuildOptions withProgress = options;
    withProgress.progress = report;
    if (levelSet) {
      // As a level set .vdb is read for `d2vdb field`: the field of the grid, keeping its voxels.
      input.emplace();
      input->path = "python.vdb";
      input->value =
          FieldInput{ApproximantField::fromLevelSet(levelSet, withProgress.field, report), false};
    }
    return buildApproximantField(std::move(*input), withProgress);
  });
  Field field;
  field.field = std::make_shared<const ApproximantField>(std::move(built.field));
  field.of = built.inputKind;
  field.warnings = std::move(built.warnings);
  field.signs = built.signs;
  return field;
}

// onAnswer(i, answerAt(points[i])) for every point, without the GIL, in parallel over fixed blocks
// of kQueryBlock points as answerAll() (io/FieldQuery.cc) runs them: each block keeps its
// accessor's leaf cache warm over consecutive points, and each answer depends on its point only.
template <typename OnAnswer>
void answerEach(const ApproximantField& field, const std::vector<Eigen::Vector3d>& points,
                int threads, const OnAnswer& onAnswer) {
  runWithoutGil(threads, [&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, points.size(), kQueryBlock),
        [&](const tbb::blocked_range<std::size_t>& range) {
          ApproximantField::Accessor accessor(field);
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            onAnswer(i, answerAt(field, accessor, points[i]));
          }
        },
        tbb::simple_partitioner());
  });
}

py::dict query(const Field& self, const py::handle& pointsArray, int threads) {
  const ApproximantField& field = fieldOf(self);
  const std::vector<Eigen::Vector3d> points = pointsFromArray(pointsArray, "points");
  const auto count = static_cast<py::ssize_t>(points.size());
  py::array_t<double> distance(count), k1(count), k2(count);
  py::array_t<double> footpoint({count, py::ssize_t{3}}), normal({count, py::ssize_t{3}}),
      e1({count, py::ssize_t{3}});
  py::array_t<std::int32_t> level(count);
  py::array_t<std::uint16_t> flags(count);
  py::array_t<std::uint8_t> status(count);
  double* distanceOut = distance.mutable_data();
  double* k1Out = k1.mutable_data();
  double* k2Out = k2.mutable_data();
  double* footpointOut = footpoint.mutable_data();
  double* normalOut = normal.mutable_data();
  double* e1Out = e1.mutable_data();
  std::int32_t* levelOut = level.mutable_data();
  std::uint16_t* flagsOut = flags.mutable_data();
  std::uint8_t* statusOut = status.mutable_data();
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  answerEach(field, points, threads, [&](std::size_t i, const FieldAnswer& answer) {
    const bool ok = answer.status == QueryStatus::Ok;
    const Approximant& a = answer.approximant;
    statusOut[i] = static_cast<std::uint8_t>(answer.status);
    levelOut[i] = answer.level;
    flagsOut[i] = ok ? a.flags : 0;
    distanceOut[i] = ok ? a.distance : nan;
    k1Out[i] = ok ? a.k1 : nan;
    k2Out[i] = ok ? a.k2 : nan;
    for (int axis = 0; axis < 3; ++axis) {
      const std::size_t at = 3 * i + static_cast<std::size_t>(axis);
      footpointOut[at] = ok ? a.footpoint[axis] : nan;
      normalOut[at] = ok ? a.normal[axis] : nan;
      e1Out[at] = ok ? a.tangent[axis] : nan;
    }
  });
  py::dict result;
  result["distance"] = distance;
  result["footpoint"] = footpoint;
  result["normal"] = normal;
  result["k1"] = k1;
  result["k2"] = k2;
  result["e1"] = e1;
  result["level"] = level;
  result["flags"] = flags;
  result["status"] = status;
  return result;
}

py::tuple sdmForm(const Field& self, const py::handle& pointsArray, int threads) {
  const ApproximantField& field = fieldOf(self);
  const std::vector<Eigen::Vector3d> points = pointsFromArray(pointsArray, "points");
  const auto count = static_cast<py::ssize_t>(points.size());
  py::array_t<double> A({count, py::ssize_t{3}, py::ssize_t{3}}), b({count, py::ssize_t{3}}),
      c(count);
  double* aOut = A.mutable_data();
  double* bOut = b.mutable_data();
  double* cOut = c.mutable_data();
  std::vector<std::uint8_t> outside(points.size(), 0);
  answerEach(field, points, threads, [&](std::size_t i, const FieldAnswer& answer) {
    if (answer.status != QueryStatus::Ok) {
      outside[i] = 1;
      return;
    }
    const QuadraticForm form = answer.approximant.form(ErrorTerm::SDM);
    for (int row = 0; row < 3; ++row) {
      for (int column = 0; column < 3; ++column) {
        aOut[9 * i + static_cast<std::size_t>(3 * row + column)] = form.A(row, column);
      }
      bOut[3 * i + static_cast<std::size_t>(row)] = form.b[row];
    }
    cOut[i] = form.c;
  });
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (outside[i]) {
      throw InputError("points[" + std::to_string(i) +
                       "]: " + outsideDomainMessage(field.domain(), points[i]));
    }
  }
  return py::make_tuple(A, b, c);
}

}  // namespace

LoadedInput inputOf(const py::handle& target, const std::filesystem::path& label) {
  LoadedInput input;
  input.path = label;
  if (py::isinstance<TriangleMesh>(target)) {
    input.value = MeshInput{target.cast<const TriangleMesh&>(), MeshFormat::Obj};
  } else if (py::isinstance<PointSet>(target)) {
    input.value = PointSetInput{target.cast<const PointSet&>().points};
  } else if (py::isinstance<BSplineCurve>(target)) {
    input.value = target.cast<const BSplineCurve&>();
  } else if (py::isinstance<BSplineSurface>(target)) {
    input.value = target.cast<const BSplineSurface&>();
  } else {
    input.value = PointSetInput{pointsFromArray(target, "target points")};
  }
  return input;
}

void bindField(py::module_& module) {
  py::class_<Field>(
      module, "Field",
      "The squared-distance approximant field of a target: a narrow band whose voxels carry "
      "footpoint, normal, principal curvatures and directions, plus coarser levels that answer "
      "anywhere in the working domain (the target's box padded by `padding` of its largest "
      "side). Immutable; queries are thread-safe.")
      .def(py::init(&buildField), py::arg("target"), py::kw_only(), py::arg("voxel_size") = 0.0,
           py::arg("resolution") = kDefaultResolution, py::arg("half_width") = 3.0,
           py::arg("padding") = 0.5, py::arg("smooth") = py::none(),
           py::arg("max_voxels") = kDefaultMaxActiveVoxels, py::arg("threads") = 0,
           py::arg("progress") = py::none(),
           "The field of a Mesh (through its level set, or with smooth='loop'/'pn' of its smooth "
           "surface), a LevelSet (keeping its voxels), a PointSet or (N, 3) points, or a Curve, "
           "as `d2vdb field` builds it. voxel_size in world units (0: the longest bounding-box "
           "side over resolution); half_width in voxels. threads: TBB threads (0: all cores), "
           "the result does not depend on it. progress: None or callable(stage, fraction). "
           "Raises InputError for empty or degenerate targets and bands over max_voxels.")
      .def("query", &query, py::arg("points"), py::kw_only(), py::arg("threads") = 0,
           "Answers at (N, 3) world points, as `d2vdb query`: a dict of arrays: distance (N,) "
           "(signed for surfaces, world units), footpoint, normal, e1 (N, 3) (e1: first "
           "principal direction, or the tangent of a curve), k1, k2 (N,) (1/world units, "
           "positive where the surface bends away from the normal), level (N,) int32 (0: the "
           "band, -1: no answer), flags (N,) uint16 (approximant flag bits) and status (N,) uint8 "
           "(0 answered, 1 outside the working domain: its values are NaN).")
      .def("sdm_form", &sdmForm, py::arg("points"), py::kw_only(), py::arg("threads") = 0,
           "The SDM quadratic forms at (N, 3) points: (A (N, 3, 3), b (N, 3), c (N,)) with "
           "Q(x) = x.A x - 2 b.x + c, the clamped second-order approximant of the squared "
           "distance (world units squared). Raises InputError for a point outside the working "
           "domain.")
      .def(
          "save",
          [](const Field& self, const std::filesystem::path& path, bool compression, bool halfFloat,
             const std::string& source) {
            const ApproximantField& field = fieldOf(self);
            VdbWriteOptions options;
            options.blosc = compression;
            options.halfFloat = halfFloat;
            options.source = source;
            options.halfWidth = field.halfWidth();
            const py::gil_scoped_release release;
            writeField(path, field, options);
          },
          py::arg("path"), py::kw_only(), py::arg("compression") = true,
          py::arg("half_float") = false, py::arg("source") = "",
          "Writes the field as `d2vdb field` does (the distance grid and its companion grids, "
          "standard OpenVDB types), atomically.")
      .def(
          "grids",
          [](const Field& self) {
            py::dict grids;
            for (const openvdb::GridBase::Ptr& grid : fieldToGrids(fieldOf(self))) {
              grids[py::str(grid->getName())] = toPyopenvdb(grid);
            }
            return grids;
          },
          "The field's grids as pyopenvdb grids by name (what save() writes): the distance grid "
          "is the field's own (treat it as read-only), the companion grids are made for the "
          "call.")
      .def_property_readonly(
          "distance_grid",
          [](const Field& self) {
            LevelSet levelSet;
            levelSet.grid = openvdb::ConstPtrCast<openvdb::FloatGrid>(fieldOf(self).distanceGrid());
            levelSet.halfWidth = fieldOf(self).halfWidth();
            return levelSet;
          },
          "The band's distance grid as a LevelSet (shared with the field: treat it as "
          "read-only).")
      .def_property_readonly(
          "voxel_size", [](const Field& self) { return fieldOf(self).voxelSize(); },
          "The band's voxel size, world units.")
      .def_property_readonly(
          "half_width", [](const Field& self) { return fieldOf(self).halfWidth(); },
          "The band's half-width, voxels.")
      .def_property_readonly(
          "kind",
          [](const Field& self) { return std::string(targetKindName(fieldOf(self).kind())); },
          "'surface', 'curve' or 'points'.")
      .def_property_readonly(
          "of", [](const Field& self) { return std::string(inputKindName(self.of)); },
          "What the field was built from: 'mesh', 'level set', 'points', 'curve', 'field' (read "
          "from a file that stored it), ...")
      .def_property_readonly(
          "domain",
          [](const Field& self) {
            const Eigen::AlignedBox3d box = fieldOf(self).domain();
            return boxTuple(box.min(), box.max());
          },
          "The working domain ((xmin, ymin, zmin), (xmax, ymax, zmax)), world units.")
      .def_property_readonly(
          "active_voxel_count",
          [](const Field& self) { return fieldOf(self).distanceGrid()->activeVoxelCount(); },
          "Voxels of the band.")
      .def_readonly("warnings", &Field::warnings)
      .def("__repr__", [](const Field& self) {
        const ApproximantField& field = fieldOf(self);
        return "<d2vdb.Field of a " + std::string(targetKindName(field.kind())) + ", " +
               std::to_string(field.distanceGrid()->activeVoxelCount()) +
               " band voxels, voxel size " + std::to_string(field.voxelSize()) + ">";
      });
}

}  // namespace d2vdb::python
