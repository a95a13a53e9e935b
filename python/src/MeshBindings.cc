// d2vdb.Mesh: triangle meshes from and to numpy arrays, their validation report and files.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "Arrays.h"
#include "Bindings.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/MeshIO.h"
#include "d2vdb/mesh/MeshMeasures.h"
#include "d2vdb/mesh/MeshValidation.h"

namespace d2vdb::python {

namespace {

std::shared_ptr<TriangleMesh> meshFromArrays(const py::handle& vertices, const py::handle& faces,
                                             const py::handle& normals) {
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->positions = positionsFromArray(vertices, "vertices");
  mesh->triangles = trianglesFromArray(faces, mesh->positions.size(), "faces");
  if (!normals.is_none()) {
    mesh->normals = positionsFromArray(normals, "normals");
    if (mesh->normals.size() != mesh->positions.size()) {
      throw InputError("normals must have one row per vertex (" +
                       std::to_string(mesh->positions.size()) + "); it has " +
                       std::to_string(mesh->normals.size()));
    }
  }
  return mesh;
}

}  // namespace

void bindMesh(py::module_& module) {
  py::class_<MeshReport>(module, "MeshReport",
                         "What Mesh.validate() found: exact counts of edges, boundary and "
                         "non-manifold edges, components, and whether the mesh is closed, "
                         "manifold and consistently oriented.")
      .def_readonly("vertex_count", &MeshReport::vertexCount)
      .def_readonly("triangle_count", &MeshReport::triangleCount)
      .def_readonly("edge_count", &MeshReport::edgeCount)
      .def_readonly("boundary_edge_count", &MeshReport::boundaryEdgeCount)
      .def_readonly("non_manifold_edge_count", &MeshReport::nonManifoldEdgeCount)
      .def_readonly("non_manifold_vertex_count", &MeshReport::nonManifoldVertexCount)
      .def_readonly("boundary_loop_count", &MeshReport::boundaryLoopCount)
      .def_readonly("degenerate_triangle_count", &MeshReport::degenerateTriangleCount)
      .def_readonly("inconsistently_oriented_edge_count",
                    &MeshReport::inconsistentlyOrientedEdgeCount)
      .def_readonly("unreferenced_vertex_count", &MeshReport::unreferencedVertexCount)
      .def_readonly("connected_component_count", &MeshReport::connectedComponentCount)
      .def_readonly("closed", &MeshReport::closed)
      .def_readonly("manifold", &MeshReport::manifold)
      .def_readonly("oriented", &MeshReport::oriented)
      .def_readonly("euler_characteristic", &MeshReport::eulerCharacteristic)
      .def_property_readonly("problems", &MeshReport::problems,
                             "One line per problem found; empty for a clean closed mesh.")
      .def("__repr__", [](const MeshReport& report) {
        return "<d2vdb.MeshReport " + std::to_string(report.triangleCount) + " triangles, " +
               (report.closed ? "closed" : "not closed") + ", " +
               std::to_string(report.connectedComponentCount) + " components>";
      });

  py::class_<TriangleMesh, std::shared_ptr<TriangleMesh>>(
      module, "Mesh",
      "An indexed triangle mesh in world units: float32 vertex positions, counter-clockwise "
      "triangles seen from outside, optional unit vertex normals.")
      .def(py::init(&meshFromArrays), py::arg("vertices"), py::arg("faces"),
           py::arg("normals") = py::none(),
           "A mesh from an (N, 3) array of vertex positions (any float dtype or order; stored as "
           "float32) and an (M, 3) array of integer vertex indices. Raises InputError for wrong "
           "shapes, NaN or infinite coordinates, and indices out of [0, N), naming the first bad "
           "element.")
      .def_property_readonly(
          "vertices",
          [](const py::object& self) {
            const auto& mesh = self.cast<const TriangleMesh&>();
            return readOnlyRows(mesh.positions.empty() ? nullptr : mesh.positions.front().data(),
                                mesh.positions.size(), self);
          },
          "(N, 3) float32 vertex positions: a read-only view of the mesh's own storage.")
      .def_property_readonly(
          "faces",
          [](const py::object& self) {
            const auto& mesh = self.cast<const TriangleMesh&>();
            return readOnlyRows(mesh.triangles.empty() ? nullptr : mesh.triangles.front().data(),
                                mesh.triangles.size(), self);
          },
          "(M, 3) uint32 vertex indices: a read-only view of the mesh's own storage.")
      .def_property_readonly(
          "normals",
          [](const py::object& self) -> py::object {
            const auto& mesh = self.cast<const TriangleMesh&>();
            if (!mesh.hasNormals()) return py::none();
            return readOnlyRows(mesh.normals.front().data(), mesh.normals.size(), self);
          },
          "(N, 3) float32 unit vertex normals (read-only view), or None.")
      .def_property_readonly("vertex_count", &TriangleMesh::vertexCount)
      .def_property_readonly("face_count", &TriangleMesh::triangleCount)
      .def_property_readonly(
          "bounding_box",
          [](const TriangleMesh& mesh) {
            const BoundingBox box = boundingBox(mesh);
            return boxTuple(box.min, box.max);
          },
          "((xmin, ymin, zmin), (xmax, ymax, zmax)) of the vertices triangles use, world units; "
          "InputError for a mesh without vertices.")
      .def("validate", &validateMesh,
           "The mesh's topology: closed, manifold, oriented, components (MeshReport).")
      .def(
          "save",
          [](const TriangleMesh& mesh, const std::filesystem::path& path, bool binary) {
            MeshWriteOptions options;
            options.binary = binary;
            const py::gil_scoped_release release;
            writeMesh(path, mesh, options);
          },
          py::arg("path"), py::arg("binary") = true,
          "Writes the mesh as .obj, .ply or .stl (by extension; PLY and STL binary unless "
          "binary=False), atomically: a failure leaves an existing file untouched. Coordinates "
          "read back bit for bit.")
      .def("__repr__", [](const TriangleMesh& mesh) {
        return "<d2vdb.Mesh " + std::to_string(mesh.vertexCount()) + " vertices, " +
               std::to_string(mesh.triangleCount()) + " triangles>";
      });
}

}  // namespace d2vdb::python
