// Measuring from Python: points projected onto B-spline curves (Curve.project) and the exact,
// certified Hausdorff distance between two curves (d2vdb.hausdorff), as `d2vdb project` and
// `d2vdb hausdorff` compute them.
#include <pybind11/numpy.h>

#include "Arrays.h"
#include "Bindings.h"
#include "LongCall.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/io/HausdorffInput.h"
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

// Any object certified_hausdorff() takes, as a Hausdorff input.
HausdorffInput hausdorffInputOfObject(const py::handle& object, const char* name) {
  if (py::isinstance<TriangleMesh>(object)) {
    return hausdorffInputOfMesh(object.cast<const TriangleMesh&>());
  }
  if (py::isinstance<LevelSet>(object)) {
    return hausdorffInputOfLevelSet(*object.cast<const LevelSet&>().grid);
  }
  if (py::isinstance<BSplineCurve>(object)) {
    return hausdorffInputOfCurve(object.cast<const BSplineCurve&>());
  }
  if (py::isinstance<BSplineSurface>(object)) {
    return hausdorffInputOfSurface(object.cast<const BSplineSurface&>());
  }
  if (py::isinstance<PointSet>(object)) {
    return hausdorffInputOfPoints(object.cast<const PointSet&>().points);
  }
  return hausdorffInputOfPoints(pointsFromArray(object, name));
}

py::tuple pointTuple(const Eigen::Vector3d& point) {
  return py::make_tuple(point.x(), point.y(), point.z());
}

py::dict bracketDict(const DirectedHausdorffBracket& bracket) {
  py::dict result;
  result["lower_bound"] = bracket.lower;
  result["upper_bound"] = bracket.upper;
  result["from_point"] = pointTuple(bracket.witness);
  result["to_point"] = pointTuple(bracket.witnessClosest);
  result["primitives_refined"] = bracket.primitivesRefined;
  result["depth"] = bracket.deepestLevel;
  result["converged"] = bracket.converged;
  result["warning"] = bracket.warning;
  std::vector<double> distances = bracket.pointDistances;
  const auto count = static_cast<py::ssize_t>(distances.size());
  result["point_distances"] = arrayOwning(std::move(distances), {count});
  return result;
}

py::dict certifiedHausdorffOf(const py::handle& a, const py::handle& b, double tolerance,
                              bool relative, bool oneSided, int maxDepth, int threads,
                              const py::object& progress) {
  const HausdorffInput inputA = hausdorffInputOfObject(a, "a");
  const HausdorffInput inputB = hausdorffInputOfObject(b, "b");
  HausdorffRequest request;
  request.tolerance = tolerance;
  request.relative = relative;
  request.oneSided = oneSided;
  request.maxDepth = maxDepth;
  const auto comparison =
      runLong<HausdorffComparison>(progress, threads, [&](const ProgressCallback& report) {
        HausdorffRequest withProgress = request;
        withProgress.progress = report;
        return compareHausdorff(inputA, inputB, withProgress);
      });
  py::dict result;
  result["lower_bound"] = comparison.result.lower;
  result["upper_bound"] = comparison.result.upper;
  result["tolerance"] = comparison.tolerance;
  result["diagonal"] = comparison.diagonal;
  result["a_to_b"] = bracketDict(comparison.result.aToB);
  if (!oneSided) result["b_to_a"] = bracketDict(comparison.result.bToA);
  result["a_as"] = comparison.a.description;
  result["b_as"] = comparison.b.description;
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
  module.def("certified_hausdorff", &certifiedHausdorffOf, py::arg("a"), py::arg("b"),
             py::kw_only(), py::arg("tolerance") = 0.0, py::arg("relative") = false,
             py::arg("one_sided") = false, py::arg("max_depth") = 0, py::arg("threads") = 0,
             py::arg("progress") = py::none(),
             "The Hausdorff distance between two shapes as a certified bracket, as `d2vdb "
             "hausdorff` computes it for meshes: a and b are each a Mesh, a LevelSet (its "
             "marching-cubes mesh), a Curve, a Surface, a PointSet or an (N, 3) array of points. "
             "tolerance is the bracket's width in world units (relative=True: of the diagonal of "
             "both shapes' box; 0: relative 1e-6). Returns a dict of lower_bound, upper_bound, "
             "tolerance (world units), diagonal, and per direction (a_to_b, b_to_a) the bracket, "
             "the witness from_point and its nearest to_point, primitives_refined, depth, "
             "converged, warning and point_distances (a's points' distances, for a mesh's heat "
             "map). Ctrl-C stops it at its next progress report.");
}

}  // namespace d2vdb::python
