// Oriented samples (points with unit normals): the input of support-function fitting.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"
#include "d2vdb/support/SphericalTriangulation.h"

namespace d2vdb {

/// Points X_i of a surface with their unit normals n_i (world units). points.size() ==
/// normals.size(); normals point out of the body (the side the support function measures).
struct OrientedSamples {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;
};

/// How checkOrientedSamples() treated the normals.
struct SampleCheck {
  std::size_t renormalized = 0;   ///< normals whose length differed from 1 by more than 1e-3
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

/// A triangle mesh seen through its Gauss map: its used vertices as oriented samples and its
/// triangles carried over to their normals (the Gauss image, a triangulation of part of the
/// sphere), with how each triangle's Gauss image is oriented.
struct MeshGaussImage {
  OrientedSamples samples;  ///< as samplesFromMesh()
  /// The mesh's triangles over samples.normals, each wound counter-clockwise on the sphere.
  SphericalTriangulation gaussImage;
  /// Triangles whose Gauss image keeps the mesh's orientation (det(n_a, n_b, n_c) > 0 for a
  /// triangle wound counter-clockwise seen from outside): convex (or concave) there.
  std::size_t preservingTriangles = 0;
  /// Triangles whose Gauss image is reversed: saddle-shaped there.
  std::size_t reversingTriangles = 0;
  /// Triangles whose corner normals are (nearly) coplanar with the origin: |det| below 1e-12 of
  /// the triangle's normal spread, so the Gauss map collapses them (flat or cylindrical parts).
  std::size_t collapsedTriangles = 0;
  bool closed = false;  ///< every edge shared by exactly two triangles
};

/// The Gauss image of a mesh with triangles (normals as samplesFromMesh() takes them). A mesh
/// whose Gauss map is injective (a closed convex mesh, or a patch whose triangles all keep or all
/// reverse orientation and do not overlap on the sphere) is what a single support function can
/// represent; preservingTriangles and reversingTriangles tell whether it is. Throws InputError
/// (naming `sourceName`) for a mesh without triangles or vertices.
MeshGaussImage meshGaussImage(const TriangleMesh& mesh, const std::string& sourceName);

}  // namespace d2vdb
