#include "d2vdb/manifold/PnTriangles.h"

#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/detail/TriangleBezier.h"

namespace d2vdb {

using detail::triangleIndex;
using Index = HalfEdgeMesh::Index;

PnTriangles::PnTriangles(std::shared_ptr<const HalfEdgeMesh> mesh,
                         std::vector<Eigen::Vector3d> normals)
    : mesh_(std::move(mesh)), normals_(std::move(normals)) {
  if (!mesh_) throw InputError("PN triangles need a mesh");
  if (normals_.size() != mesh_->vertexCount()) {
    throw InputError("PN triangles need one normal per vertex: " + std::to_string(normals_.size()) +
                     " normals for " + std::to_string(mesh_->vertexCount()) + " vertices");
  }
  for (Index v = 0; v < mesh_->vertexCount(); ++v) {
    if (mesh_->degree(v) == 0) continue;
    if (!normals_[v].allFinite() || std::abs(normals_[v].norm() - 1.0) > 1e-6) {
      throw InputError("the normal of vertex " + std::to_string(v) +
                       " is not a finite unit vector");
    }
  }
}

PnTriangles::PnTriangles(std::shared_ptr<const HalfEdgeMesh> mesh) : mesh_(std::move(mesh)) {
  if (!mesh_) throw InputError("PN triangles need a mesh");
  normals_.assign(mesh_->vertexCount(), Eigen::Vector3d::Zero());
  for (Index f = 0; f < mesh_->faceCount(); ++f) {
    const Eigen::Vector3d& a = mesh_->position(mesh_->corner(f, 0));
    const Eigen::Vector3d& b = mesh_->position(mesh_->corner(f, 1));
    const Eigen::Vector3d& c = mesh_->position(mesh_->corner(f, 2));
    const Eigen::Vector3d areaNormal = (b - a).cross(c - a);  // twice the area, outward
    for (int k = 0; k < 3; ++k) normals_[mesh_->corner(f, k)] += areaNormal;
  }
  for (Index v = 0; v < mesh_->vertexCount(); ++v) {
    if (mesh_->degree(v) == 0) {
      normals_[v] = Eigen::Vector3d::UnitZ();
      continue;
    }
    const double length = normals_[v].norm();
    if (!(length > 0.0) || !std::isfinite(length)) {
      throw InputError("vertex " + std::to_string(v) +
                       " has no normal: its triangles have no area");
    }
    normals_[v] /= length;
  }
}

std::array<Eigen::Vector3d, 10> PnTriangles::controlNet(Index face) const {
  const Index i0 = mesh_->corner(face, 0);
  const Index i1 = mesh_->corner(face, 1);
  const Index i2 = mesh_->corner(face, 2);
  const Eigen::Vector3d& p1 = mesh_->position(i0);
  const Eigen::Vector3d& p2 = mesh_->position(i1);
  const Eigen::Vector3d& p3 = mesh_->position(i2);
  const Eigen::Vector3d& n1 = normals_[i0];
  const Eigen::Vector3d& n2 = normals_[i1];
  const Eigen::Vector3d& n3 = normals_[i2];
  // The edge point near Pi toward Pj: (2 Pi + Pj - ((Pj - Pi) . Ni) Ni) / 3.
  const auto edge = [](const Eigen::Vector3d& pi, const Eigen::Vector3d& pj,
                       const Eigen::Vector3d& ni) -> Eigen::Vector3d {
    return (2.0 * pi + pj - (pj - pi).dot(ni) * ni) / 3.0;
  };
  const Eigen::Vector3d b210 = edge(p1, p2, n1);
  const Eigen::Vector3d b120 = edge(p2, p1, n2);
  const Eigen::Vector3d b021 = edge(p2, p3, n2);
  const Eigen::Vector3d b012 = edge(p3, p2, n3);
  const Eigen::Vector3d b102 = edge(p3, p1, n3);
  const Eigen::Vector3d b201 = edge(p1, p3, n1);
  const Eigen::Vector3d e = (b210 + b120 + b021 + b012 + b102 + b201) / 6.0;
  const Eigen::Vector3d center = (p1 + p2 + p3) / 3.0;
  std::array<Eigen::Vector3d, 10> net;
  // Layout: b_{ijk} with i, j, k the exponents of b0, b1, b2 at triangleIndex(3, j, k).
  net[triangleIndex(3, 0, 0)] = p1;    // b300
  net[triangleIndex(3, 3, 0)] = p2;    // b030
  net[triangleIndex(3, 0, 3)] = p3;    // b003
  net[triangleIndex(3, 1, 0)] = b210;  // two parts P1, one part P2
  net[triangleIndex(3, 2, 0)] = b120;
  net[triangleIndex(3, 2, 1)] = b021;
  net[triangleIndex(3, 1, 2)] = b012;
  net[triangleIndex(3, 0, 2)] = b102;
  net[triangleIndex(3, 0, 1)] = b201;
  net[triangleIndex(3, 1, 1)] = e + (e - center) / 2.0;  // b111
  return net;
}

void PnTriangles::positions(Index face, const Eigen::Vector3d* bary, std::size_t count,
                            Eigen::Vector3d* out) const {
  const std::array<Eigen::Vector3d, 10> net = controlNet(face);
  for (std::size_t i = 0; i < count; ++i) {
    out[i] = detail::evaluateTriangleBezier<3>(net, bary[i][1], bary[i][2], 0).position;
  }
}

SourceJet PnTriangles::evaluate(const FacePoint& point) const {
  const detail::PatchJet jet =
      detail::evaluateTriangleBezier<3>(controlNet(point.face), point.bary[1], point.bary[2], 1);
  SourceJet result;
  result.position = jet.position;
  result.d1 = jet.dv;
  result.d2 = jet.dw;
  return result;
}

}  // namespace d2vdb
