// Oriented samples (points with unit normals): the input of support-function fitting.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb {

/// Points X_i of a surface with their unit normals n_i (world units). points.size() ==
/// normals.size(); normals point out of the body (the side the support function measures).
struct OrientedSamples {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;
};

/// How checkOrientedSamples() treated the normals.
struct SampleCheck {
  std::size_t renormalised = 0;   ///< normals whose length differed from 1 by more than 1e-3
  double largestDeviation = 0.0;  ///< max | |n_i| - 1 | over all samples
};

/// Validates `samples` and normalises every normal in place. Throws InputError (naming
/// `sourceName` and the sample index) for mismatched sizes, no samples, a non-finite point or
/// normal, or a normal shorter than 1e-150 (zero). Normals whose length is off by more than 1e-3
/// are normalised too and counted in the result (the caller warns): many tools write unnormalised
/// normals, and only their direction matters.
SampleCheck checkOrientedSamples(OrientedSamples& samples, const std::string& sourceName);

/// The vertices of `mesh` with their normals: every vertex that a triangle uses (or all vertices
/// of a mesh without triangles, i.e. a point set). Uses mesh.normals when the mesh has one per
/// vertex, else area-weighted vertex normals (VertexNormals.h) when it has triangles. Throws
/// InputError (naming `sourceName`) for a mesh without vertices, or a point set without normals.
OrientedSamples samplesFromMesh(const TriangleMesh& mesh, const std::string& sourceName);

}  // namespace d2vdb
