// The surface a parametric pseudo-manifold is fitted to: defined face by face over a closed mesh.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <string>

#include "d2vdb/manifold/HalfEdgeMesh.h"

namespace d2vdb {

/// Position and first derivatives of a source surface at a face point, the derivatives taken with
/// respect to the barycentric coordinates (b1, b2) of the face (b0 = 1 - b1 - b2).
struct SourceJet {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d d1 = Eigen::Vector3d::Zero();
  Eigen::Vector3d d2 = Eigen::Vector3d::Zero();
  /// False where the face parametrisation has no derivative (at an extraordinary vertex of a
  /// subdivision surface); position is valid everywhere.
  bool derivativesValid = true;
};

/// A continuous surface made of one parametric patch per face of a closed mesh, patches agreeing
/// along shared edges: the Loop limit surface (LoopLimitSurface.h) or PN triangles
/// (PnTriangles.h). Immutable; all members are thread-safe.
class SourceSurface {
 public:
  virtual ~SourceSurface() = default;

  /// The mesh whose faces parametrise the surface.
  virtual const HalfEdgeMesh& mesh() const = 0;
  /// The mesh, shared.
  virtual std::shared_ptr<const HalfEdgeMesh> sharedMesh() const = 0;

  /// Positions of `count` points of one face (barycentric coordinates bary[i]) into out[i]. The
  /// face's control data are gathered once for the whole batch. Barycentric coordinates must be
  /// those of points of the face (non-negative, sum 1, up to round-off).
  virtual void positions(HalfEdgeMesh::Index face, const Eigen::Vector3d* bary, std::size_t count,
                         Eigen::Vector3d* out) const = 0;

  /// Position and first derivatives at one point.
  virtual SourceJet evaluate(const FacePoint& point) const = 0;

  /// Short name: "loop" or "pn".
  virtual std::string name() const = 0;
};

}  // namespace d2vdb
