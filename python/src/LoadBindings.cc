// d2vdb.load(): any input file, recognised by its content, as the object it holds.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "Arrays.h"
#include "Bindings.h"
#include "LongCall.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/io/InputFile.h"

namespace d2vdb::python {

namespace {

py::object wrap(LoadedInput&& input) {
  switch (input.kind()) {
    case InputKind::Mesh:
      return py::cast(std::make_shared<TriangleMesh>(std::move(input).take<MeshInput>().mesh));
    case InputKind::PointSet:
      return py::cast(PointSet{std::move(input).take<PointSetInput>().points});
    case InputKind::LevelSet: {
      LevelSet levelSet;
      levelSet.grid = std::move(input).take<LevelSetInput>().floatGrid();
      return py::cast(std::move(levelSet));
    }
    case InputKind::Field: {
      Field field;
      field.field =
          std::make_shared<const ApproximantField>(std::move(input).take<FieldInput>().field);
      field.of = InputKind::Field;
      return py::cast(std::move(field));
    }
    case InputKind::Curve:
      return py::cast(std::move(input).take<BSplineCurve>());
    case InputKind::Surface:
      return py::cast(std::move(input).take<BSplineSurface>());
    case InputKind::SupportFunction:
      return py::cast(SupportFunctionObject{std::move(input).take<SupportFunctionDocument>()});
    case InputKind::Polylines: {
      py::list polylines;
      for (const Polyline& polyline : std::move(input).take<PolylinesInput>().polylines) {
        std::vector<Eigen::Vector3d> points(polyline.points.begin(), polyline.points.end());
        polylines.append(arrayOfPoints(points));
      }
      return std::move(polylines);
    }
    case InputKind::VdbGrids:
      break;
  }
  throw RuntimeFailure("load(): an input kind the module does not wrap");
}

}  // namespace

void bindLoad(py::module_& module) {
  module.def(
      "load",
      [](const std::filesystem::path& path, const std::string& grid, int threads,
         const py::object& progress) {
        requireExistingFile(path);
        LoadOptions options;
        options.purpose = "d2vdb.load()";
        options.gridName = grid;
        LoadedInput input =
            runLong<LoadedInput>(progress, threads, [&](const ProgressCallback& report) {
              LoadOptions withProgress = options;
              withProgress.progress = report;
              return loadInput(path,
                               {InputKind::Mesh, InputKind::PointSet, InputKind::Field,
                                InputKind::LevelSet, InputKind::Curve, InputKind::Surface,
                                InputKind::Polylines, InputKind::SupportFunction},
                               withProgress);
            });
        return wrap(std::move(input));
      },
      py::arg("path"), py::kw_only(), py::arg("grid") = "", py::arg("threads") = 0,
      py::arg("progress") = py::none(),
      "Reads any file d2vdb reads, recognised by its content: a Mesh (.obj, .ply with faces, "
      ".stl), a PointSet (.xyz, .ply without faces), a LevelSet (a .vdb level set; `grid` names "
      "the grid, default the first float level set), a Field (a .vdb written by `d2vdb field` or "
      "Field.save()), a Curve or Surface (B-spline .json), a list of (n, 3) arrays (polyline "
      ".json) or a SupportFunction (.json). Raises FileNotFoundError for a missing file and "
      "InputError for malformed, truncated or non-finite content, naming the line or byte.");
}

}  // namespace d2vdb::python
