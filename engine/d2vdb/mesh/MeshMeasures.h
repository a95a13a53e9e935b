// Simple measures of a triangle mesh: bounding box and surface area.
#pragma once

#include <Eigen/Core>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// Axis-aligned bounding box in world units.
struct BoundingBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(0.0);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(0.0);
  Eigen::Vector3d extent() const { return max - min; }
};

/// Bounding box of the vertices referenced by triangles (all vertices if there are no triangles).
/// Throws InputError for a mesh without vertices.
BoundingBox boundingBox(const TriangleMesh& mesh);

/// Total triangle area in world units squared (computed in double precision).
double surfaceArea(const TriangleMesh& mesh);

}  // namespace d2vdb
