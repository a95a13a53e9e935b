// The indexed triangle mesh every d2vdb module exchanges.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace d2vdb {

/// An indexed triangle mesh in world units (float positions, as OpenVDB's mesh tools take them).
/// Triangles index into `positions` with counter-clockwise winding seen from outside (so the
/// right-hand normal points outward). `normals` is either empty or holds one unit normal per
/// position. The struct itself enforces nothing; validateMesh() (MeshValidation.h) reports on it
/// and the readers only ever return meshes whose indices are in range and coordinates finite.
struct TriangleMesh {
  using Index = std::uint32_t;
  using Triangle = std::array<Index, 3>;

  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;
  std::vector<Triangle> triangles;

  std::size_t vertexCount() const { return positions.size(); }
  std::size_t triangleCount() const { return triangles.size(); }
  bool hasNormals() const { return !normals.empty() && normals.size() == positions.size(); }
};

}  // namespace d2vdb
