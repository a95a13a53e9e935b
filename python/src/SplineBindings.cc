// d2vdb.Curve, d2vdb.Surface and d2vdb.PointSet: the engine's B-spline curves, tensor-product
// surfaces and point sets, from and to arrays and their files.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>

#include "Arrays.h"
#include "Bindings.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/io/PointSetFile.h"
#include "d2vdb/io/SplineJson.h"
#include "d2vdb/spline/BSplineCurve.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb::python {

namespace {

std::vector<double> parametersFromArray(const py::handle& object, const std::string& what) {
  const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!array || array.ndim() > 1) throw InputError(what + " must be a number or a 1-D array");
  std::vector<double> values(array.data(), array.data() + array.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw InputError(what + "[" + std::to_string(i) + "] is not finite");
    }
  }
  return values;
}

KnotVector knotsOrClamped(const py::object& knots, int degree, int count, const std::string& what) {
  if (knots.is_none()) return KnotVector::clamped(degree, count);
  return KnotVector(degree, parametersFromArray(knots, what));
}

py::array_t<double> knotArray(const KnotVector& knots) {
  std::vector<double> values = knots.values();
  const auto size = static_cast<py::ssize_t>(values.size());
  return arrayOwning(std::move(values), {size});
}

BSplineCurve makeCurve(const py::handle& controlPoints, int degree, bool closed,
                       const py::object& knots, int dimension) {
  std::vector<Eigen::Vector3d> points = pointsFromArray(controlPoints, "control_points");
  const int count = static_cast<int>(points.size());
  if (closed) {
    if (!knots.is_none())
      return BSplineCurve(KnotVector(degree, parametersFromArray(knots, "knots")),
                          std::move(points), dimension, true);
    return BSplineCurve::closed(degree, std::move(points), dimension);
  }
  return BSplineCurve(knotsOrClamped(knots, degree, count, "knots"), std::move(points), dimension,
                      false);
}

BSplineSurface makeSurface(const py::handle& controlPoints, int degreeU, int degreeV,
                           const py::object& knotsU, const py::object& knotsV) {
  const auto grid =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(controlPoints);
  if (!grid || grid.ndim() != 3 || grid.shape(2) != 3) {
    throw InputError("control_points must have shape (count_u, count_v, 3)");
  }
  const int countU = static_cast<int>(grid.shape(0));
  const int countV = static_cast<int>(grid.shape(1));
  const py::array flat = grid.attr("reshape")(-1, 3);
  std::vector<Eigen::Vector3d> points = pointsFromArray(flat, "control_points");
  return BSplineSurface(knotsOrClamped(knotsU, degreeU, countU, "knots_u"),
                        knotsOrClamped(knotsV, degreeV, countV, "knots_v"), std::move(points));
}

void bindPointSet(py::module_& module) {
  py::class_<PointSet>(module, "PointSet", "Points in world units, in file order.")
      .def(py::init([](const py::handle& points) {
             return PointSet{pointsFromArray(points, "points")};
           }),
           py::arg("points"), "From an (N, 3) array of finite coordinates.")
      .def_property_readonly(
          "points", [](const PointSet& set) { return arrayOfPoints(set.points); },
          "(N, 3) float64 copy of the points.")
      .def("__len__", [](const PointSet& set) { return set.points.size(); })
      .def(
          "save",
          [](const PointSet& set, const std::filesystem::path& path) {
            const py::gil_scoped_release release;
            writePointSet(path, set.points);
          },
          py::arg("path"), "Writes an .xyz file (one 'x y z' line per point), atomically.");
}

void bindCurve(py::module_& module) {
  py::class_<BSplineCurve>(
      module, "Curve",
      "A B-spline curve in 2D or 3D (world units), open (clamped) or closed (uniform periodic).")
      .def(py::init(&makeCurve), py::arg("control_points"), py::kw_only(), py::arg("degree") = 3,
           py::arg("closed") = false, py::arg("knots") = py::none(), py::arg("dimension") = 3,
           "From (n, 3) control points. Open curves: clamped uniform knots unless `knots` is "
           "given (n + degree + 1 values); closed curves: the n unique control points on uniform "
           "periodic knots. Raises InputError for counts that do not match.")
      .def_property_readonly("degree", &BSplineCurve::degree)
      .def_property_readonly("closed", &BSplineCurve::isClosed)
      .def_property_readonly("dimension", &BSplineCurve::dimension)
      .def_property_readonly("knots",
                             [](const BSplineCurve& curve) { return knotArray(curve.knots()); })
      .def_property_readonly("domain",
                             [](const BSplineCurve& curve) {
                               return py::make_tuple(curve.domain().start, curve.domain().end);
                             })
      .def_property_readonly(
          "control_points",
          [](const BSplineCurve& curve) { return arrayOfPoints(curve.controlPoints()); },
          "(n, 3) float64 copy of the stored control points.")
      .def(
          "evaluate",
          [](const BSplineCurve& curve, const py::handle& parameters) {
            const std::vector<double> t = parametersFromArray(parameters, "t");
            std::vector<Eigen::Vector3d> points(t.size());
            for (std::size_t i = 0; i < t.size(); ++i) points[i] = curve.evaluate(t[i]);
            return arrayOfPoints(points);
          },
          py::arg("t"),
          "C(t) at each parameter: (N, 3). Raises InputError outside an open curve's domain.")
      .def(
          "save",
          [](const BSplineCurve& curve, const std::filesystem::path& path) {
            writeCurveJson(path, curve);
          },
          py::arg("path"),
          "Writes the curve's .json file (the format every command reads), atomically.");
}

void bindSurface(py::module_& module) {
  py::class_<BSplineSurface>(module, "Surface", "A tensor-product B-spline surface (world units).")
      .def(py::init(&makeSurface), py::arg("control_points"), py::kw_only(),
           py::arg("degree_u") = 3, py::arg("degree_v") = 3, py::arg("knots_u") = py::none(),
           py::arg("knots_v") = py::none(),
           "From a (count_u, count_v, 3) control grid on clamped uniform knots unless knots are "
           "given.")
      .def_property_readonly("degree_u", &BSplineSurface::degreeU)
      .def_property_readonly("degree_v", &BSplineSurface::degreeV)
      .def_property_readonly("closed_u", &BSplineSurface::isClosedU)
      .def_property_readonly("closed_v", &BSplineSurface::isClosedV)
      .def_property_readonly("knots_u",
                             [](const BSplineSurface& s) { return knotArray(s.knotsU()); })
      .def_property_readonly("knots_v",
                             [](const BSplineSurface& s) { return knotArray(s.knotsV()); })
      .def_property_readonly(
          "control_points",
          [](const BSplineSurface& surface) {
            return arrayOfPoints(surface.controlPoints())
                .attr("reshape")(surface.countU(), surface.countV(), 3);
          },
          "(count_u, count_v, 3) float64 copy of the control grid.")
      .def(
          "evaluate",
          [](const BSplineSurface& surface, const py::handle& u, const py::handle& v) {
            const std::vector<double> us = parametersFromArray(u, "u");
            const std::vector<double> vs = parametersFromArray(v, "v");
            if (us.size() != vs.size()) throw InputError("u and v must have the same length");
            std::vector<Eigen::Vector3d> points(us.size());
            for (std::size_t i = 0; i < us.size(); ++i) points[i] = surface.evaluate(us[i], vs[i]);
            return arrayOfPoints(points);
          },
          py::arg("u"), py::arg("v"), "S(u, v) at each parameter pair: (N, 3).")
      .def(
          "save",
          [](const BSplineSurface& surface, const std::filesystem::path& path) {
            writeSurfaceJson(path, surface);
          },
          py::arg("path"), "Writes the surface's .json file, atomically.");
}

}  // namespace

void bindSplines(py::module_& module) {
  bindPointSet(module);
  bindCurve(module);
  bindSurface(module);
}

}  // namespace d2vdb::python
