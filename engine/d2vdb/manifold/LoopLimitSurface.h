// The limit surface of Loop subdivision over a closed triangle mesh, evaluated exactly.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "d2vdb/manifold/SourceSurface.h"

namespace d2vdb {

namespace detail {
struct ExtraordinaryTemplate;
}

/// The Loop subdivision limit surface (Loop, "Smooth subdivision surfaces based on triangles",
/// M.S. thesis, University of Utah, 1987) of a closed mesh, evaluated exactly at any (face,
/// barycentric) point without subdividing the mesh globally:
/// - a face whose three corners have degree 6 is a quartic box-spline patch of its 12 neighbouring
///   vertices, written once as a quartic Bézier net;
/// - a face with exactly one corner of degree != 6 (extraordinary) is evaluated as in Stam,
///   "Evaluation of Loop subdivision surfaces" (SIGGRAPH 1998 course notes): its (N + 6)-vertex
///   neighbourhood is subdivided k times, k being the first level at which the point leaves the
///   sub-triangle at the extraordinary corner, and the point is evaluated on one of the three
///   regular sub-patches there (the subdivision matrix is applied k times rather than through its
///   eigen-decomposition: the same exact values without assuming the matrix is diagonalisable);
///   at the extraordinary vertex itself, Loop's limit-position mask;
/// - a face with two or three extraordinary corners is evaluated on the four faces of one global
///   Loop subdivision step (each of which has at most one extraordinary corner).
/// Loop's rules: vertex weight beta(N) = (5/8 - (3/8 + cos(2 pi / N) / 4)^2) / N, edge points 3/8,
/// 3/8, 1/8, 1/8. The surface is C2 except at extraordinary vertices, where it is C1. Affine maps
/// of the mesh map the surface alike (every rule is an affine combination).
///
/// Derivatives are with respect to the face's barycentric coordinates (b1, b2); at an
/// extraordinary vertex itself they do not exist (derivativesValid = false).
class LoopLimitSurface final : public SourceSurface {
 public:
  /// The limit surface of `mesh`. Throws InputError for a null mesh.
  explicit LoopLimitSurface(std::shared_ptr<const HalfEdgeMesh> mesh);
  ~LoopLimitSurface() override;

  const HalfEdgeMesh& mesh() const override { return *mesh_; }
  std::shared_ptr<const HalfEdgeMesh> sharedMesh() const override { return mesh_; }
  void positions(HalfEdgeMesh::Index face, const Eigen::Vector3d* bary, std::size_t count,
                 Eigen::Vector3d* out) const override;
  SourceJet evaluate(const FacePoint& point) const override;
  std::string name() const override { return "loop"; }

  /// Number of faces with two or three extraordinary corners, evaluated through one subdivision
  /// step.
  std::size_t subdividedFaceCount() const { return subdividedFaces_; }
  /// Number of faces with exactly one extraordinary corner.
  std::size_t extraordinaryFaceCount() const { return extraordinaryFaces_; }

  /// The limit position of a mesh vertex (Loop's limit mask). Throws InputError for an unused or
  /// missing vertex.
  Eigen::Vector3d limitPosition(HalfEdgeMesh::Index vertex) const;
  /// The limit normal (unit, outward for a counter-clockwise mesh) at a mesh vertex, from Loop's
  /// tangent masks. Throws InputError for an unused or missing vertex.
  Eigen::Vector3d limitNormal(HalfEdgeMesh::Index vertex) const;

 private:
  /// A mesh level: the input mesh or its one-step subdivision.
  struct Level {
    std::shared_ptr<const HalfEdgeMesh> mesh;
    /// Per face: 3 = regular, 0..2 = the extraordinary corner, 4 = evaluate on the finer level.
    std::vector<std::uint8_t> kind;
  };
  enum : std::uint8_t { kRegular = 3, kSubdivided = 4 };

  void classify(Level& level, bool allowSubdivision);
  const detail::ExtraordinaryTemplate& templateFor(int valence) const;
  /// Evaluates points of a face of `level` whose kind is regular or extraordinary: positions
  /// into positions[i], and with first derivatives into jets[i] when jets is not null.
  void evaluateFace(const Level& level, HalfEdgeMesh::Index face, const Eigen::Vector3d* bary,
                    std::size_t count, Eigen::Vector3d* positions, SourceJet* jets) const;

  /// The data of the face a thread evaluated last (see evaluateFace).
  struct FaceCache {
    std::uint64_t owner = 0;
    const Level* level = nullptr;
    HalfEdgeMesh::Index face = 0;
    std::array<Eigen::Vector3d, 15> net;   ///< regular face: quartic Bézier net
    Eigen::Vector3d limit;                 ///< extraordinary: limit point of the corner
    std::vector<Eigen::MatrixX3d> levels;  ///< extraordinary: template per level
    std::vector<std::array<std::array<Eigen::Vector3d, 15>, 3>> nets;  ///< sub-patch nets
    std::vector<std::array<bool, 3>> haveNet;
  };

  std::uint64_t id_ = 0;  ///< distinct for every instance of the process (cache key)
  std::shared_ptr<const HalfEdgeMesh> mesh_;
  Level base_;
  std::unique_ptr<Level> fine_;
  std::map<int, std::unique_ptr<detail::ExtraordinaryTemplate>> templates_;
  std::size_t subdividedFaces_ = 0;
  std::size_t extraordinaryFaces_ = 0;
};

}  // namespace d2vdb
