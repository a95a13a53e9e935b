#include "JsonReports.h"

#include "d2vdb/field/MeshToLevelSet.h"

namespace d2vdb::cli {

nlohmann::json signReportJson(const SignReport& report) {
  return {
      {"method", signMethodName(report.method)},
      {"corrected_voxels", report.correctedVoxels},
      {"winding_number_queries", report.windingNumberQueries},
      {"reoriented_triangles", report.reorientedTriangles},
      {"watertight", report.watertight},
      {"holes_closed", report.holesClosed},
      {"self_intersecting", report.selfIntersecting},
      {"pockets_filled", report.pocketsFilled},
      {"pocket_voxels", report.pocketVoxels},
      {"hole_voxels", report.holeVoxels},
  };
}

std::string signSummary(const SignReport& report) {
  std::string text = std::string("signs checked by ") + signMethodName(report.method) + ": " +
                     std::to_string(report.correctedVoxels) +
                     " voxels of OpenVDB's conversion corrected";
  if (report.pocketsFilled > 0) {
    text += ", " + std::to_string(report.pocketsFilled) + " pockets of open parts filled (" +
            std::to_string(report.pocketVoxels) + " voxels)";
  }
  if (report.holeVoxels > 0) {
    text += ", " + std::to_string(report.holeVoxels) +
            " voxels added where the surfaces closing holes leave the band";
  }
  return text + "\n";
}

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

nlohmann::json pointJson(const Eigen::Vector3d& point, int dimension) {
  if (dimension == 2) return {point.x(), point.y()};
  return {point.x(), point.y(), point.z()};
}

Eigen::Vector3d pointFromJson(const nlohmann::json& values) {
  return {values.at(0).get<double>(), values.at(1).get<double>(), values.at(2).get<double>()};
}

nlohmann::json boxJson(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  return {{"min", pointJson(min)}, {"max", pointJson(max)}};
}

}  // namespace d2vdb::cli
