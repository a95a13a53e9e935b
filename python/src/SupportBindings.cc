// d2vdb.SupportFunction: support functions fitted to oriented samples or a field, evaluated and
// tessellated at exact offsets, as `d2vdb support` and `d2vdb offset` do over the whole sphere.
#include <pybind11/numpy.h>

#include "Arrays.h"
#include "Bindings.h"
#include "LongCall.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/io/SupportFunctionJson.h"
#include "d2vdb/io/SupportInput.h"
#include "d2vdb/support/SupportOffsets.h"
#include "d2vdb/support/SupportTessellation.h"

namespace d2vdb::python {

void bindSupport(py::module_& module) {
  py::class_<SupportFunctionObject>(
      module, "SupportFunction",
      "A support function h on the unit sphere of normals, in spherical harmonics: the surface "
      "x_h(n) = h(n) n + grad_S h(n) and its exact offsets x_h(n) + r n (world units), as `d2vdb "
      "support` and `d2vdb offset` fit, check and tessellate it.")
      .def_static(
          "fit",
          [](const py::handle& target, const py::object& normals, int degree,
             const std::optional<double>& regularization, bool allowSingular, int threads) {
            SupportInput input;
            if (py::isinstance<Field>(target)) {
              if (!normals.is_none()) throw InputError("a Field gives its own normals");
              input.kind = SupportInputKind::Field;
              input.samples = samplesFromField(*target.cast<const Field&>().field, "the field");
            } else {
              if (normals.is_none()) {
                throw InputError("fit() takes (N, 3) points with their (N, 3) normals, or a Field");
              }
              input.kind = SupportInputKind::Points;
              input.samples.points = pointsFromArray(target, "points");
              input.samples.normals = pointsFromArray(normals, "normals");
              if (input.samples.points.size() != input.samples.normals.size()) {
                throw InputError("points and normals must have the same length");
              }
            }
            SupportFitSettings settings;
            settings.degree = degree;
            settings.regularization = regularization ? *regularization : -1.0;
            settings.allowSingular = allowSingular;
            CheckedSupport checked;
            runWithoutGil(threads, [&] { checked = fitAndCheck(input, "python", settings); });
            return SupportFunctionObject{std::move(checked.document)};
          },
          py::arg("points"), py::arg("normals") = py::none(), py::kw_only(), py::arg("degree") = 16,
          py::arg("regularization") = py::none(), py::arg("allow_singular") = false,
          py::arg("threads") = 0,
          "Fits a support function over the whole sphere to (N, 3) points with their unit "
          "normals, or to the band footpoints of a surface's Field, as `d2vdb support` does "
          "(degree L: (L + 1)^2 harmonics; regularization None: the default). Raises "
          "InputError for samples that determine no function, and, unless allow_singular, for "
          "a function that is singular (the surface is not convex) or misses its samples.")
      .def_property_readonly(
          "degree",
          [](const SupportFunctionObject& support) { return support.document.function.degree(); })
      .def(
          "value",
          [](const SupportFunctionObject& support, const py::handle& normals) {
            const std::vector<Eigen::Vector3d> directions = pointsFromArray(normals, "normals");
            std::vector<double> values(directions.size());
            for (std::size_t i = 0; i < directions.size(); ++i) {
              values[i] = support.document.function.value(directions[i]);
            }
            const auto count = static_cast<py::ssize_t>(values.size());
            return arrayOwning(std::move(values), {count});
          },
          py::arg("normals"), "h(n) at (N, 3) normals (normalised first): (N,), world units.")
      .def(
          "points",
          [](const SupportFunctionObject& support, const py::handle& normals, double offset) {
            const std::vector<Eigen::Vector3d> directions = pointsFromArray(normals, "normals");
            return arrayOfPoints(support.document.function.points(directions, offset));
          },
          py::arg("normals"), py::arg("offset") = 0.0,
          "The surface points x_h(n) + offset n with normal n: (N, 3), world units.")
      .def(
          "tessellate",
          [](const SupportFunctionObject& support, double offset, int subdivisions) {
            const SphericalTriangulation domain =
                tessellationDomain(support.document.patch, subdivisions);
            return std::make_shared<TriangleMesh>(
                tessellateSupport(support.document.function, domain, offset));
          },
          py::arg("offset") = 0.0, py::kw_only(), py::arg("subdivisions") = 6,
          "The exact offset at signed distance `offset` as a mesh, as `d2vdb offset` makes it: "
          "one vertex per normal of its patch, or of a geodesic sphere with 10 * 4^subdivisions "
          "+ 2 normals. Vertices lie on the offset surface exactly (to float rounding).")
      .def(
          "save",
          [](const SupportFunctionObject& support, const std::filesystem::path& path) {
            writeSupportFunctionJson(path, support.document);
          },
          py::arg("path"), "Writes the support-function .json, atomically.")
      .def("to_json", [](const SupportFunctionObject& support) {
        return supportFunctionToJson(support.document);
      });
}

}  // namespace d2vdb::python
