// Exact evaluation of the Loop limit surface: regular faces as box-spline patches, faces at
// extraordinary corners by Stam's subdivision.
#include "d2vdb/manifold/LoopLimitSurface.h"

#include <Eigen/Geometry>

#include <tbb/parallel_for.h>

#include <array>
#include <atomic>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/LoopSubdivision.h"
#include "d2vdb/manifold/detail/ChartMath.h"
#include "d2vdb/manifold/detail/LoopPatches.h"
#include "d2vdb/manifold/detail/TriangleBezier.h"

namespace d2vdb {

using detail::ExtraordinaryTemplate;
using detail::PatchJet;
using Index = HalfEdgeMesh::Index;

namespace {

/// The 12 control vertices of the regular face `face` (corners p0, p1, p2 in face order), in the
/// order of detail::kRegularLattice.
std::array<Eigen::Vector3d, 12> regularControls(const HalfEdgeMesh& mesh, Index face) {
  const Index h0 = 3 * face;
  const Index h1 = h0 + 1;
  const Index h2 = h0 + 2;
  const Index p0 = mesh.from(h0);
  const Index p1 = mesh.from(h1);
  const Index p2 = mesh.from(h2);
  const int k0 = mesh.ringIndex(h0);
  const int k1 = mesh.ringIndex(h1);
  const int k2 = mesh.ringIndex(h2);
  const auto around = [&](Index v, int k) { return mesh.position(mesh.to(mesh.ring(v, k))); };
  std::array<Eigen::Vector3d, 12> controls;
  controls[0] = mesh.position(p0);
  controls[1] = mesh.position(p1);
  controls[2] = mesh.position(p2);
  controls[6] = around(p0, k0 + 2);   // (-1, 1)
  controls[3] = around(p0, k0 + 3);   // (-1, 0)
  controls[4] = around(p0, k0 + 4);   // (0, -1)
  controls[5] = around(p0, k0 + 5);   // (1, -1)
  controls[9] = around(p1, k1 + 3);   // (2, -1)
  controls[7] = around(p1, k1 + 4);   // (2, 0)
  controls[8] = around(p1, k1 + 5);   // (1, 1)
  controls[10] = around(p2, k2 + 3);  // (0, 2)
  controls[11] = around(p2, k2 + 4);  // (-1, 2)
  return controls;
}

/// The template of the face whose corner `corner` is extraordinary (ExtraordinaryTemplate order).
Eigen::MatrixX3d extraordinaryControls(const HalfEdgeMesh& mesh, Index face, int corner) {
  const Index h = 3 * face + static_cast<Index>(corner);
  const Index c = mesh.from(h);
  const int n = mesh.degree(c);
  Eigen::MatrixX3d controls(n + 6, 3);
  controls.row(0) = mesh.position(c).transpose();
  const int kc = mesh.ringIndex(h);
  for (int i = 1; i <= n; ++i) {
    controls.row(i) = mesh.position(mesh.to(mesh.ring(c, kc + i - 1))).transpose();
  }
  const Index toN2 = HalfEdgeMesh::next(h);  // n1 -> n2
  const Index n1 = mesh.from(toN2);
  const int k1 = mesh.ringIndex(toN2);
  const Index toC = HalfEdgeMesh::prev(h);  // n2 -> c
  const Index n2 = mesh.from(toC);
  const int k2 = mesh.ringIndex(toC);
  controls.row(n + 1) = mesh.position(mesh.to(mesh.ring(n1, k1 + 3))).transpose();  // b
  controls.row(n + 2) = mesh.position(mesh.to(mesh.ring(n1, k1 + 4))).transpose();  // a
  controls.row(n + 3) = mesh.position(mesh.to(mesh.ring(n1, k1 + 5))).transpose();  // m
  controls.row(n + 4) = mesh.position(mesh.to(mesh.ring(n2, k2 + 3))).transpose();  // d
  controls.row(n + 5) = mesh.position(mesh.to(mesh.ring(n2, k2 + 4))).transpose();  // e
  return controls;
}

/// Derivatives with respect to the local (v, w) of corner `corner` turned into derivatives with
/// respect to the face's (b1, b2).
void toFaceDerivatives(int corner, const Eigen::Vector3d& dv, const Eigen::Vector3d& dw,
                       SourceJet& out) {
  switch (corner) {
    case 0:  // (v, w) = (b1, b2)
      out.d1 = dv;
      out.d2 = dw;
      break;
    case 1:  // (v, w) = (b2, b0)
      out.d1 = -dw;
      out.d2 = dv - dw;
      break;
    default:  // (v, w) = (b0, b1)
      out.d1 = -dv + dw;
      out.d2 = -dv;
      break;
  }
}

/// Which of the four faces of one subdivision step holds `bary`, and the barycentric coordinates
/// there; derivatives with respect to the fine (b1, b2) turn into coarse ones by `toCoarse`.
int subFace(const Eigen::Vector3d& bary, Eigen::Vector3d& fine) {
  if (bary[0] >= 0.5) {
    fine = {2.0 * bary[0] - 1.0, 2.0 * bary[1], 2.0 * bary[2]};
    return 0;
  }
  if (bary[1] >= 0.5) {
    fine = {2.0 * bary[0], 2.0 * bary[1] - 1.0, 2.0 * bary[2]};
    return 1;
  }
  if (bary[2] >= 0.5) {
    fine = {2.0 * bary[0], 2.0 * bary[1], 2.0 * bary[2] - 1.0};
    return 2;
  }
  fine = {1.0 - 2.0 * bary[2], 1.0 - 2.0 * bary[0], 1.0 - 2.0 * bary[1]};
  return 3;
}

void toCoarse(int sub, SourceJet& jet) {
  if (sub < 3) {
    jet.d1 *= 2.0;
    jet.d2 *= 2.0;
  } else {
    // fine b1 = -1 + 2 b1 + 2 b2, fine b2 = 1 - 2 b1.
    const Eigen::Vector3d f1 = jet.d1;
    const Eigen::Vector3d f2 = jet.d2;
    jet.d1 = 2.0 * f1 - 2.0 * f2;
    jet.d2 = 2.0 * f1;
  }
}

}  // namespace

LoopLimitSurface::LoopLimitSurface(std::shared_ptr<const HalfEdgeMesh> mesh)
    : mesh_(std::move(mesh)) {
  static std::atomic<std::uint64_t> instances{0};
  id_ = ++instances;
  if (!mesh_) throw InputError("the Loop limit surface needs a mesh");
  base_.mesh = mesh_;
  classify(base_, true);
  if (subdividedFaces_ > 0) {
    fine_ = std::make_unique<Level>();
    fine_->mesh = std::make_shared<const HalfEdgeMesh>(loopSubdivision(*mesh_));
    classify(*fine_, false);
  }
}

LoopLimitSurface::~LoopLimitSurface() = default;

void LoopLimitSurface::classify(Level& level, bool allowSubdivision) {
  const HalfEdgeMesh& mesh = *level.mesh;
  level.kind.assign(mesh.faceCount(), kRegular);
  for (Index f = 0; f < mesh.faceCount(); ++f) {
    int extraordinary = 0;
    int corner = 0;
    for (int k = 0; k < 3; ++k) {
      if (mesh.degree(mesh.corner(f, k)) != 6) {
        ++extraordinary;
        corner = k;
      }
    }
    if (extraordinary == 1) {
      level.kind[f] = static_cast<std::uint8_t>(corner);
      const int n = mesh.degree(mesh.corner(f, corner));
      if (templates_.count(n) == 0) {
        templates_.emplace(n, std::make_unique<ExtraordinaryTemplate>(n));
      }
      if (allowSubdivision) ++extraordinaryFaces_;
    } else if (extraordinary > 1) {
      if (!allowSubdivision) {
        // Cannot happen: after one step every face has at most one extraordinary corner.
        throw InputError("internal error: a subdivided face has two extraordinary corners");
      }
      level.kind[f] = kSubdivided;
      ++subdividedFaces_;
    }
  }
}

const ExtraordinaryTemplate& LoopLimitSurface::templateFor(int valence) const {
  return *templates_.at(valence);
}

void LoopLimitSurface::evaluateFace(const Level& level, Index face, const Eigen::Vector3d* bary,
                                    std::size_t count, Eigen::Vector3d* positions,
                                    SourceJet* jets) const {
  const HalfEdgeMesh& mesh = *level.mesh;
  const std::uint8_t kind = level.kind[face];
  // The face's gathered data stay in a per-thread cache: projections and batches ask for the
  // same face many times in a row. The cached values are computed exactly as fresh ones, so
  // results do not depend on what a thread evaluated before.
  thread_local FaceCache cache;
  if (cache.owner != id_ || cache.level != &level || cache.face != face) {
    cache.owner = id_;
    cache.level = &level;
    cache.face = face;
    cache.levels.clear();
    cache.nets.clear();
    cache.haveNet.clear();
    if (kind == kRegular) {
      cache.net = detail::regularNet(regularControls(mesh, face));
    } else {
      // The template is subdivided relative to the limit point of c: every rule is affine, and
      // the offsets shrink with the sub-triangles, so points near c keep their relative
      // precision (the differences that give derivatives do not cancel against the absolute
      // position).
      const ExtraordinaryTemplate& tmpl = templateFor(mesh.degree(mesh.corner(face, kind)));
      cache.levels.push_back(extraordinaryControls(mesh, face, kind));
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int j = 1; j < tmpl.size() - 5; ++j) sum += cache.levels[0].row(j).transpose();
      cache.limit =
          tmpl.limitCenter * cache.levels[0].row(0).transpose() + tmpl.limitNeighbor * sum;
      cache.levels[0].rowwise() -= cache.limit.transpose();
    }
  }
  if (kind == kRegular) {
    const std::array<Eigen::Vector3d, 15>& net = cache.net;
    for (std::size_t i = 0; i < count; ++i) {
      if (jets == nullptr) {
        positions[i] = detail::triangleBezierPosition<4>(net, bary[i][1], bary[i][2]);
        continue;
      }
      const PatchJet jet = detail::evaluateTriangleBezier<4>(net, bary[i][1], bary[i][2], 1);
      positions[i] = jet.position;
      jets[i].position = jet.position;
      jets[i].d1 = jet.dv;
      jets[i].d2 = jet.dw;
      jets[i].derivativesValid = true;
    }
    return;
  }
  const int corner = kind;
  const ExtraordinaryTemplate& tmpl = templateFor(mesh.degree(mesh.corner(face, corner)));
  // levels[j]: the template after j subdivision steps; nets[j][t]: Bézier net of sub-patch t of
  // level j + 1 (computed on demand).
  std::vector<Eigen::MatrixX3d>& levels = cache.levels;
  std::vector<std::array<std::array<Eigen::Vector3d, 15>, 3>>& nets = cache.nets;
  std::vector<std::array<bool, 3>>& haveNet = cache.haveNet;
  const Eigen::Vector3d limit = cache.limit;
  for (std::size_t i = 0; i < count; ++i) {
    const double v = bary[i][(corner + 1) % 3];
    const double w = bary[i][(corner + 2) % 3];
    if (!(v + w > 0.0)) {
      positions[i] = limit;
      if (jets != nullptr) {
        jets[i].position = limit;
        jets[i].d1.setZero();
        jets[i].d2.setZero();
        jets[i].derivativesValid = false;
      }
      continue;
    }
    // The point lies in sub-triangle T1, T2 or T3 of level `depth` (depth >= 1) once
    // (V, W) = 2^(depth - 1) (v, w) has V + W in (1/2, 1].
    int depth = 1;
    double scale = 1.0;
    while ((v + w) * scale <= 0.5) {
      scale *= 2.0;
      ++depth;
    }
    const double bigV = v * scale;
    const double bigW = w * scale;
    int patch = 1;
    double localV = 1.0 - 2.0 * bigV;
    double localW = 1.0 - 2.0 * bigW;
    if (bigV > 0.5) {
      patch = 0;
      localV = 2.0 * bigV - 1.0;
      localW = 2.0 * bigW;
    } else if (bigW > 0.5) {
      patch = 2;
      localV = 2.0 * bigV;
      localW = 2.0 * bigW - 1.0;
    }
    // Small products: coefficient-wise (lazyProduct), no packing for a general product.
    while (static_cast<int>(levels.size()) < depth) {
      levels.push_back(tmpl.step.lazyProduct(levels.back()));
    }
    if (static_cast<int>(nets.size()) < depth) {
      nets.resize(depth);
      haveNet.resize(depth, {false, false, false});
    }
    if (!haveNet[depth - 1][patch]) {
      const Eigen::Matrix<double, 15, 3> net =
          tmpl.subPatchNet[patch].lazyProduct(levels[depth - 1]);
      for (int j = 0; j < 15; ++j) nets[depth - 1][patch][j] = net.row(j).transpose();
      haveNet[depth - 1][patch] = true;
    }
    const std::array<Eigen::Vector3d, 15>& net = nets[depth - 1][patch];
    if (jets == nullptr) {
      positions[i] = limit + detail::triangleBezierPosition<4>(net, localV, localW);
      continue;
    }
    const PatchJet jet = detail::evaluateTriangleBezier<4>(net, localV, localW, 1);
    positions[i] = limit + jet.position;
    jets[i].position = positions[i];
    jets[i].derivativesValid = true;
    // d/dv = (+-) 2 scale d/dlocalV (the centre sub-patch T2 is turned by a half turn).
    const double factor = (patch == 1 ? -2.0 : 2.0) * scale;
    toFaceDerivatives(corner, factor * jet.dv, factor * jet.dw, jets[i]);
  }
}

void LoopLimitSurface::positions(Index face, const Eigen::Vector3d* bary, std::size_t count,
                                 Eigen::Vector3d* out) const {
  if (base_.kind[face] != kSubdivided) {
    evaluateFace(base_, face, bary, count, out, nullptr);
    return;
  }
  // Group the points by the sub-face that holds them.
  std::array<std::vector<Eigen::Vector3d>, 4> fineBary;
  std::array<std::vector<std::size_t>, 4> which;
  for (std::size_t i = 0; i < count; ++i) {
    Eigen::Vector3d fine;
    const int sub = subFace(bary[i], fine);
    fineBary[sub].push_back(fine);
    which[sub].push_back(i);
  }
  std::vector<Eigen::Vector3d> finePositions;
  for (int sub = 0; sub < 4; ++sub) {
    if (which[sub].empty()) continue;
    finePositions.resize(which[sub].size());
    evaluateFace(*fine_, 4 * face + static_cast<Index>(sub), fineBary[sub].data(),
                 which[sub].size(), finePositions.data(), nullptr);
    for (std::size_t j = 0; j < which[sub].size(); ++j) out[which[sub][j]] = finePositions[j];
  }
}

SourceJet LoopLimitSurface::evaluate(const FacePoint& point) const {
  SourceJet jet;
  Eigen::Vector3d position;
  if (base_.kind[point.face] != kSubdivided) {
    evaluateFace(base_, point.face, &point.bary, 1, &position, &jet);
    return jet;
  }
  Eigen::Vector3d fine;
  const int sub = subFace(point.bary, fine);
  evaluateFace(*fine_, 4 * point.face + static_cast<Index>(sub), &fine, 1, &position, &jet);
  toCoarse(sub, jet);
  return jet;
}

Eigen::Vector3d LoopLimitSurface::limitPosition(Index vertex) const {
  if (vertex >= mesh_->vertexCount() || mesh_->degree(vertex) == 0) {
    throw InputError("vertex " + std::to_string(vertex) + " is not a vertex of the surface");
  }
  const int n = mesh_->degree(vertex);
  const double beta = detail::loopBeta(n);
  const double chi = 1.0 / (3.0 / (8.0 * beta) + n);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k) sum += mesh_->position(mesh_->to(mesh_->ring(vertex, k)));
  return (1.0 - n * chi) * mesh_->position(vertex) + chi * sum;
}

Eigen::Vector3d LoopLimitSurface::limitNormal(Index vertex) const {
  if (vertex >= mesh_->vertexCount() || mesh_->degree(vertex) == 0) {
    throw InputError("vertex " + std::to_string(vertex) + " is not a vertex of the surface");
  }
  const int n = mesh_->degree(vertex);
  Eigen::Vector3d t1 = Eigen::Vector3d::Zero();
  Eigen::Vector3d t2 = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d p = mesh_->position(mesh_->to(mesh_->ring(vertex, k)));
    const double angle = 2.0 * kPi * k / n;
    t1 += std::cos(angle) * p;
    t2 += std::sin(angle) * p;
  }
  return t1.cross(t2).normalized();
}

}  // namespace d2vdb
