// The C++ references of the module's benchmark (tools/bench/bench_python.py), timed inside the
// extension so that Python's overhead is what the ratio measures: the engine's batch query
// answerAll() and a surface fit called directly, without the module's argument conversion,
// worker thread and GIL release. Underscored: not part of the module's API.
#include <pybind11/numpy.h>

#include <chrono>

#include "Arrays.h"
#include "Bindings.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/fit/SurfaceFitter.h"
#include "d2vdb/io/FieldQuery.h"
#include "d2vdb/io/FitTarget.h"

namespace d2vdb::python {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void bindBenchmarkHooks(py::module_& module) {
  module.def(
      "_answer_all_seconds",
      [](const Field& field, const py::handle& pointsArray) {
        if (!field.field) throw InputError("the field holds nothing");
        const std::vector<Eigen::Vector3d> points = pointsFromArray(pointsArray, "points");
        const py::gil_scoped_release release;
        const auto start = std::chrono::steady_clock::now();
        const std::vector<FieldAnswer> answers = answerAll(*field.field, points);
        return secondsSince(start);
      },
      py::arg("field"), py::arg("points"),
      "Benchmark reference: seconds of the engine's answerAll() over the points (C++ only).");
  module.def(
      "_fit_surface_seconds",
      [](const Field& field, const BSplineSurface& initial) {
        const py::gil_scoped_release release;
        const auto start = std::chrono::steady_clock::now();
        FitTargetOptions options;
        options.spline = FitSpline::Surface;
        const FitTarget target = fitTargetFromField(field.field, "the field", options);
        const SurfaceFitResult result =
            fitSurface(initial, target.fitTarget(), SurfaceFitOptions{});
        return secondsSince(start);
      },
      py::arg("field"), py::arg("initial"),
      "Benchmark reference: seconds of a C++ surface fit with default options: the field's fit "
      "target (fitTargetFromField()) and fitSurface().");
}

}  // namespace d2vdb::python
