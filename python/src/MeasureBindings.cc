// Measuring from Python: points projected onto B-spline curves (Curve.project) and the exact,
// certified Hausdorff distance between two curves (d2vdb.hausdorff), as `d2vdb project` and
// `d2vdb hausdorff` compute them.
#include <pybind11/numpy.h>

#include "Arrays.h"
#include "Bindings.h"
#include "LongCall.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/measure/CurveHausdorff.h"
#include "d2vdb/measure/PointProjection.h"

namespace d2vdb::python {

namespace {

py::dict oneSidedDict(const OneSidedHausdorff& side) {
  py::dict result;
  result["distance"] = side.distance;
  result["lower_bound"] = side.lowerBound;
  result["upper_bound"] = side.upperBound;
  result["from_parameter"] = side.fromParameter;
  result["to_parameter"] = side.toParameter;
  result["from_point"] = py::make_tuple(side.fromPoint.x(), side.fromPoint.y(), side.fromPoint.z());
  result["to_point"] = py::make_tuple(side.toPoint.x(), side.toPoint.y(), side.toPoint.z());
  result["case"] = hausdorffCaseName(side.pairCase);
  result["converged"] = side.converged;
  result["warnings"] = side.warnings;
  return result;
}

py::dict projectOnto(const BSplineCurve& curve, const py::handle& pointsArray, int threads) {
  const std::vector<Eigen::Vector3d> points = pointsFromArray(pointsArray, "points");
  std::vector<PointProjection> projections;
  runWithoutGil(threads, [&] { projections = projectPoints(curve, points); });
  std::vector<double> parameters(points.size()), distances(points.size());
  std::vector<Eigen::Vector3d> nearest(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    parameters[i] = projections[i].parameter;
    distances[i] = projections[i].distance;
    nearest[i] = projections[i].point;
  }
  const auto count = static_cast<py::ssize_t>(points.size());
  py::dict result;
  result["parameter"] = arrayOwning(std::move(parameters), {count});
  result["point"] = arrayOfPoints(nearest);
  result["distance"] = arrayOwning(std::move(distances), {count});
  return result;
}

}  // namespace

void bindMeasure(py::module_& module) {
  py::class_<BSplineCurve> curve =
      py::reinterpret_borrow<py::class_<BSplineCurve>>(module.attr("Curve"));
  curve.def("project", &projectOnto, py::arg("points"), py::kw_only(), py::arg("threads") = 0,
            "The nearest curve point of each of (N, 3) points, found exactly (Bernstein root "
            "isolation of (C(t) - p) . C'(t) = 0, Chen et al. 2010), as `d2vdb project`: a dict "
            "of parameter (N,), point (N, 3) and distance (N,) (world units).");
  module.def(
      "hausdorff",
      [](const BSplineCurve& a, const BSplineCurve& b, double tolerance, int maxDepth,
         bool oneSided, int threads, const py::object& progress) {
        HausdorffOptions options;
        options.relativeTolerance = tolerance;
        options.maxDepth = maxDepth;
        py::dict result;
        if (oneSided) {
          const auto side = runLong<OneSidedHausdorff>(
              progress, threads,
              [&](const ProgressCallback&) { return oneSidedHausdorff(a, b, options); });
          result["distance"] = side.distance;
          result["lower_bound"] = side.lowerBound;
          result["upper_bound"] = side.upperBound;
          result["a_to_b"] = oneSidedDict(side);
          return result;
        }
        const auto both = runLong<HausdorffDistance>(
            progress, threads,
            [&](const ProgressCallback&) { return hausdorffDistance(a, b, options); });
        result["distance"] = both.distance;
        result["lower_bound"] = both.lowerBound;
        result["upper_bound"] = both.upperBound;
        result["a_to_b"] = oneSidedDict(both.aToB);
        result["b_to_a"] = oneSidedDict(both.bToA);
        result["a_to_b_is_larger"] = both.aToBIsLarger;
        return result;
      },
      py::arg("a"), py::arg("b"), py::kw_only(), py::arg("tolerance") = 1e-10,
      py::arg("max_depth") = 64, py::arg("one_sided") = false, py::arg("threads") = 0,
      py::arg("progress") = py::none(),
      "The exact Hausdorff distance between two B-spline curves (Chen, Ma, Xu and Paul 2010), as "
      "`d2vdb hausdorff`: a dict of distance, the certified bracket lower_bound <= H <= "
      "upper_bound (its width at most `tolerance` times the pair's size), and per direction "
      "(a_to_b, b_to_a) the distance, bracket, the pair's parameters and points and which of the "
      "four cases it is. one_sided=True computes h(a -> b) only. The call reports no progress "
      "(Ctrl-C waits for it to end).");
}

}  // namespace d2vdb::python
