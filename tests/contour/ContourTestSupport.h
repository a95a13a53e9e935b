// Shared helpers for the contour tests: grids filled from analytic distances and mesh checks.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <functional>
#include <string>

#include <openvdb/openvdb.h>

#include "d2vdb/mesh/MeshValidation.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::test {

/// A signed distance function in world units (negative inside).
using DistanceFunction = std::function<double(const Eigen::Vector3d&)>;

/// A narrow-band level set filled voxel by voxel from `distance` over the index box `bounds`:
/// voxel (i, j, k) centred at (i, j, k) * voxelSize, active where |d| < halfWidth * voxelSize,
/// inside voxels and tiles at -background (signed flood fill). Built independently of the
/// engine's field module.
template <typename GridT>
typename GridT::Ptr gridFromDistance(const DistanceFunction& distance, double voxelSize,
                                     double halfWidth, const openvdb::CoordBBox& bounds);

/// Exact signed distance of a torus about the z axis through `center` (world units).
double torusDistance(const Eigen::Vector3d& point, const Eigen::Vector3d& center, double major,
                     double minor);

/// Expects a closed, 2-manifold, consistently oriented mesh without degenerate triangles and
/// with the given Euler characteristic.
void expectClosedManifold(const TriangleMesh& mesh, long eulerCharacteristic,
                          const std::string& what);

/// Signed volume enclosed by a closed mesh (positive when triangles wind outward).
double signedVolume(const TriangleMesh& mesh);

}  // namespace d2vdb::test
