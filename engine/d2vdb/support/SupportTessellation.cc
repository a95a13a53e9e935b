#include "d2vdb/support/SupportTessellation.h"

#include <cmath>
#include <utility>

#include "d2vdb/core/Error.h"

namespace d2vdb {

TriangleMesh tessellateSupport(const SupportFunction& h, SphericalTriangulation domain,
                               double offset) {
  if (!std::isfinite(offset)) throw InputError("the offset distance is not finite");
  validateSphericalTriangulation(domain, "the tessellation domain");
  const std::vector<SupportPoint> points = h.evaluate(domain.normals);
  TriangleMesh mesh;
  mesh.positions.reserve(points.size());
  mesh.normals.reserve(points.size());
  std::vector<bool> reversing(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SupportPoint& p = points[i];
    mesh.positions.push_back((p.point + offset * p.normal).cast<float>());
    mesh.normals.push_back(p.normal.cast<float>());
    reversing[i] = (p.radius1 + offset) * (p.radius2 + offset) < 0.0;
  }
  mesh.triangles.reserve(domain.triangles.size());
  for (const auto& tri : domain.triangles) {
    if (reversing[tri[0]] && reversing[tri[1]] && reversing[tri[2]]) {
      mesh.triangles.push_back({tri[0], tri[2], tri[1]});
    } else {
      mesh.triangles.push_back({tri[0], tri[1], tri[2]});
    }
  }
  return mesh;
}

}  // namespace d2vdb
