#include "JsonReports.h"

namespace d2vdb::cli {

nlohmann::json meshReportJson(const MeshReport& report) {
  return {
      {"vertices", report.vertexCount},
      {"triangles", report.triangleCount},
      {"edges", report.edgeCount},
      {"closed", report.closed},
      {"manifold", report.manifold},
      {"oriented", report.oriented},
      {"boundary_edges", report.boundaryEdgeCount},
      {"boundary_loops", report.boundaryLoopCount},
      {"non_manifold_edges", report.nonManifoldEdgeCount},
      {"non_manifold_vertices", report.nonManifoldVertexCount},
      {"degenerate_triangles", report.degenerateTriangleCount},
      {"inconsistently_oriented_edges", report.inconsistentlyOrientedEdgeCount},
      {"unreferenced_vertices", report.unreferencedVertexCount},
      {"components", report.connectedComponentCount},
      {"euler_characteristic", report.eulerCharacteristic},
  };
}

nlohmann::json boundingBoxJson(const BoundingBox& box) {
  return {{"min", {box.min.x(), box.min.y(), box.min.z()}},
          {"max", {box.max.x(), box.max.y(), box.max.z()}}};
}

}  // namespace d2vdb::cli
