#include "d2vdb/manifold/ChartAtlas.h"

#include <cmath>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/detail/ChartMath.h"

namespace d2vdb {

using detail::kCos30;

using detail::PolarMap;

double ChartAtlas::radius(int degree) {
  return std::cos(kPi / degree);
}

Eigen::Vector2d ChartAtlas::canonical(const Eigen::Vector3d& bary, int corner) {
  return detail::canonicalPoint(bary, corner);
}

bool ChartAtlas::inChart(const Eigen::Vector3d& bary, int corner) {
  return detail::canonicalPoint(bary, corner).squaredNorm() < kCos30 * kCos30;
}

ChartPoint ChartAtlas::toChart(const FacePoint& point, int corner) const {
  const HalfEdgeMesh::Index halfEdge = 3 * point.face + static_cast<HalfEdgeMesh::Index>(corner);
  const HalfEdgeMesh::Index vertex = mesh_->from(halfEdge);
  const PolarMap map = detail::polarMapOf(mesh_->degree(vertex));
  return {vertex,
          map.toChart(detail::canonicalPoint(point.bary, corner), mesh_->ringIndex(halfEdge))};
}

FacePoint ChartAtlas::fromChart(const ChartPoint& point) const {
  if (point.vertex >= mesh_->vertexCount() || mesh_->degree(point.vertex) == 0) {
    throw InputError("vertex " + std::to_string(point.vertex) + " has no chart");
  }
  const int n = mesh_->degree(point.vertex);
  const PolarMap map = detail::polarMapOf(n);
  if (!point.p.allFinite() || point.p.norm() >= map.chartRadius) {
    throw InputError("the chart point lies outside the chart of vertex " +
                     std::to_string(point.vertex));
  }
  int k = 0;
  const Eigen::Vector2d z = map.toCanonical(point.p, n, k);
  const HalfEdgeMesh::Index halfEdge = mesh_->ring(point.vertex, k);
  const int corner = static_cast<int>(halfEdge % 3);
  const Eigen::Vector3d local = detail::cornerBary(z);
  FacePoint result;
  result.face = HalfEdgeMesh::face(halfEdge);
  result.bary[corner] = local[0];
  result.bary[(corner + 1) % 3] = local[1];
  result.bary[(corner + 2) % 3] = local[2];
  return result;
}

std::optional<Eigen::Vector2d> ChartAtlas::transition(HalfEdgeMesh::Index halfEdge,
                                                      const Eigen::Vector2d& p) const {
  const HalfEdgeMesh::Index u = mesh_->from(halfEdge);
  const HalfEdgeMesh::Index v = mesh_->to(halfEdge);
  const int nu = mesh_->degree(u);
  const int nv = mesh_->degree(v);
  const PolarMap mapU = detail::polarMapOf(nu);
  const PolarMap mapV = detail::polarMapOf(nv);
  if (!p.allFinite() || p.norm() >= mapU.chartRadius) return std::nullopt;
  // Angle of p relative to the edge u -> v, in (-pi, pi].
  double beta = std::atan2(p.y(), p.x()) - mapU.sector * mesh_->ringIndex(halfEdge);
  while (beta <= -kPi) beta += 2.0 * kPi;
  while (beta > kPi) beta -= 2.0 * kPi;
  if (std::abs(beta) >= mapU.sector) return std::nullopt;
  // The hexagon of u (v at 1), then the hexagon of v (u at 1).
  const double r = p.norm() / mapU.radiusScale;
  const double alpha = beta / mapU.angleScale;
  const Eigen::Vector2d z(1.0 - r * std::cos(alpha), -r * std::sin(alpha));
  const double rv = z.norm();
  if (rv >= kCos30) return std::nullopt;
  const double angle = std::atan2(z.y(), z.x()) * mapV.angleScale +
                       mapV.sector * mesh_->ringIndex(mesh_->twin(halfEdge));
  const double rho = rv * mapV.radiusScale;
  return Eigen::Vector2d(rho * std::cos(angle), rho * std::sin(angle));
}

}  // namespace d2vdb
