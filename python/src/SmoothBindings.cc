// d2vdb.SmoothSurface: the C-infinity surface of a closed triangle mesh (parametric
// pseudo-manifold over its Loop limit surface or PN triangles; Siqueira et al. 2009), evaluated
// at face points and tessellated, as `d2vdb smooth` builds it.
#include <pybind11/numpy.h>

#include <cmath>

#include "Arrays.h"
#include "Bindings.h"
#include "LongCall.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/SmoothSurfaceFromMesh.h"
#include "d2vdb/manifold/SmoothTessellation.h"

namespace d2vdb::python {

namespace {

struct SmoothSurface {
  std::shared_ptr<const MeshSmoothSurface> smooth;
};

// Face points from (N,) face indices and (N, 3) barycentric coordinates (non-negative, summing
// to 1 within 1e-9).
std::vector<FacePoint> facePointsFrom(const py::handle& faces, const py::handle& barycentric,
                                      std::size_t faceCount) {
  const auto ids =
      py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(faces);
  if (!ids || ids.ndim() != 1) throw InputError("face_ids must be a 1-D array of face indices");
  const std::vector<Eigen::Vector3d> weights = pointsFromArray(barycentric, "barycentric");
  if (weights.size() != static_cast<std::size_t>(ids.shape(0))) {
    throw InputError("face_ids and barycentric must have the same length (" +
                     std::to_string(ids.shape(0)) + " and " + std::to_string(weights.size()) + ")");
  }
  std::vector<FacePoint> points(weights.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::int64_t face = ids.data()[i];
    if (face < 0 || static_cast<std::size_t>(face) >= faceCount) {
      throw InputError("face_ids[" + std::to_string(i) + "] is " + std::to_string(face) +
                       "; faces are 0 to " + std::to_string(faceCount - 1));
    }
    const Eigen::Vector3d& b = weights[i];
    if (b.minCoeff() < 0.0 || std::abs(b.sum() - 1.0) > 1e-9) {
      throw InputError("barycentric[" + std::to_string(i) + "] must be non-negative and sum to 1");
    }
    points[i] = FacePoint{static_cast<std::uint32_t>(face), b};
  }
  return points;
}

py::dict evaluate(const SmoothSurface& self, const py::handle& faces, const py::handle& barycentric,
                  int threads) {
  const std::vector<FacePoint> points =
      facePointsFrom(faces, barycentric, self.smooth->mesh->faceCount());
  std::vector<SmoothPoint> answers;
  runWithoutGil(threads,
                [&] { answers = self.smooth->surface.evaluate(points, Derivatives::Second); });
  std::vector<Eigen::Vector3d> positions(points.size()), normals(points.size()), e1(points.size());
  std::vector<double> k1(points.size()), k2(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    positions[i] = answers[i].position;
    normals[i] = answers[i].normal;
    e1[i] = answers[i].e1;
    k1[i] = answers[i].k1;
    k2[i] = answers[i].k2;
  }
  const auto count = static_cast<py::ssize_t>(points.size());
  py::dict result;
  result["position"] = arrayOfPoints(positions);
  result["normal"] = arrayOfPoints(normals);
  result["k1"] = arrayOwning(std::move(k1), {count});
  result["k2"] = arrayOwning(std::move(k2), {count});
  result["e1"] = arrayOfPoints(e1);
  return result;
}

}  // namespace

void bindSmooth(py::module_& module) {
  py::class_<SmoothSurface>(
      module, "SmoothSurface",
      "The C-infinity surface of a closed, 2-manifold, consistently oriented triangle mesh: one "
      "chart per vertex, a Bezier patch per chart fitted to the source surface (the exact Loop "
      "limit surface, or PN triangles), blended with C-infinity weights (Siqueira et al. 2009). "
      "Points are addressed by face and barycentric coordinates of the input mesh.")
      .def(py::init([](const TriangleMesh& mesh, const std::string& source, int maxBidegree,
                       int threads, const py::object& progress) {
             SmoothSurfaceFromMeshOptions options;
             if (source == "loop") {
               options.source = SmoothSurfaceSource::LoopLimit;
             } else if (source == "pn") {
               options.source = SmoothSurfaceSource::PnTriangles;
             } else {
               throw InputError("source must be 'loop' or 'pn'; got '" + source + "'");
             }
             options.fileNormals = true;
             options.surface.maxBidegree = maxBidegree;
             auto built =
                 runLong<MeshSmoothSurface>(progress, threads, [&](const ProgressCallback& report) {
                   return smoothSurfaceFromMesh(mesh, options, report);
                 });
             return SmoothSurface{std::make_shared<const MeshSmoothSurface>(std::move(built))};
           }),
           py::arg("mesh"), py::kw_only(), py::arg("source") = "loop", py::arg("max_bidegree") = 7,
           py::arg("threads") = 0, py::arg("progress") = py::none(),
           "Builds the surface as `d2vdb smooth` does (PN triangles take the mesh's own vertex "
           "normals when it has them). Raises InputError for a mesh that is not closed, manifold "
           "and consistently oriented.")
      .def("evaluate", &evaluate, py::arg("face_ids"), py::arg("barycentric"), py::kw_only(),
           py::arg("threads") = 0,
           "The surface at face points: (N,) face indices of the input mesh and (N, 3) "
           "barycentric coordinates of its corners (non-negative, summing to 1). A dict of "
           "position, normal (unit, outward), e1 (N, 3) and k1 >= k2 (N,) (1/world units, "
           "positive where the surface bends away from the normal).")
      .def(
          "tessellate",
          [](const SmoothSurface& self, int lod, bool curvature, int threads) {
            checkSmoothTessellation(*self.smooth->mesh, lod);
            SmoothTessellation tessellation;
            runWithoutGil(threads, [&] {
              tessellation = tessellateSmooth(self.smooth->surface, lod, curvature);
            });
            py::dict result;
            result["mesh"] = std::make_shared<TriangleMesh>(std::move(tessellation.mesh));
            if (curvature) {
              const auto count = static_cast<py::ssize_t>(tessellation.k1.size());
              result["k1"] = arrayOwning(std::move(tessellation.k1), {count});
              result["k2"] = arrayOwning(std::move(tessellation.k2), {count});
              result["e1"] = arrayOfPoints(tessellation.e1);
            }
            return result;
          },
          py::arg("lod") = 3, py::kw_only(), py::arg("curvature") = false, py::arg("threads") = 0,
          "A watertight mesh with 4^lod triangles per input face and the surface's own vertex "
          "normals, as `d2vdb smooth --lod` writes it: a dict with 'mesh' and, with "
          "curvature=True, per-vertex k1, k2 (N,) and e1 (N, 3).")
      .def_property_readonly(
          "face_count", [](const SmoothSurface& self) { return self.smooth->mesh->faceCount(); });
}

}  // namespace d2vdb::python
