#include "d2vdb/mesh/SurfaceTessellation.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

// The parameter of grid line k in one direction (see tessellate() for the spacing).
double gridParameter(const ParameterInterval& domain, bool closed, int samples, int k) {
  const int divisions = closed ? samples : samples - 1;
  return domain.at(static_cast<double>(k) / divisions);
}

void requireSamples(int samples, bool closed, const char* direction) {
  const int minimum = closed ? 3 : 2;
  if (samples < minimum) {
    throw InputError(std::string("tessellate: ") + std::to_string(samples) + " samples in " +
                     direction + " are too few (expected at least " + std::to_string(minimum) +
                     (closed ? " for a closed direction)" : ")"));
  }
}

// The typical magnitude of |Su| |Sv|: (control box diagonal)^2 / (domain lengths). Cross
// products below 1e-10 of it count as vanishing (rounding leaves ~1e-16 at a pole).
double crossProductScale(const BSplineSurface& surface) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& point : surface.controlPoints()) box.extend(point);
  const double diagonal = box.diagonal().norm();
  return diagonal * diagonal / (surface.domainU().length() * surface.domainV().length());
}

// The unit normal Su x Sv at (u, v), or zero where it vanishes (see crossProductScale()).
Eigen::Vector3d unitNormal(const BSplineSurface& surface, double u, double v, double scale) {
  const SurfaceDerivatives d = surface.derivatives(u, v);
  const Eigen::Vector3d normal = d.du.cross(d.dv);
  if (normal.norm() > 1e-10 * scale) return normal.normalized();
  return Eigen::Vector3d::Zero();
}

// Towards the inside of the domain from t: +1 unless t is at the end (for closed directions any
// side is inside).
double inward(const ParameterInterval& domain, double t) {
  return t < domain.end ? 1.0 : -1.0;
}

// The limit of the unit normal at a degenerate point (u, v) (e.g. a pole), approached from inside
// the domain along the diagonal; zero if it stays degenerate up to 1e-3 of the domain.
Eigen::Vector3d limitNormal(const BSplineSurface& surface, double u, double v, double scale) {
  const ParameterInterval domainU = surface.domainU();
  const ParameterInterval domainV = surface.domainV();
  for (const double fraction : {1e-7, 1e-5, 1e-3}) {
    const double shiftedU = u + inward(domainU, u) * fraction * domainU.length();
    const double shiftedV = v + inward(domainV, v) * fraction * domainV.length();
    const Eigen::Vector3d normal = unitNormal(surface, shiftedU, shiftedV, scale);
    if (!normal.isZero(0.0)) return normal;
  }
  return Eigen::Vector3d::Zero();
}

}  // namespace

TriangleMesh tessellate(const BSplineSurface& surface, int samplesU, int samplesV) {
  requireSamples(samplesU, surface.isClosedU(), "u");
  requireSamples(samplesV, surface.isClosedV(), "v");
  const std::size_t vertexCount =
      static_cast<std::size_t>(samplesU) * static_cast<std::size_t>(samplesV);
  if (vertexCount > std::numeric_limits<TriangleMesh::Index>::max()) {
    throw InputError("tessellate: a " + std::to_string(samplesU) + " x " +
                     std::to_string(samplesV) + " grid has more than 2^32 - 1 vertices");
  }

  const double scale = crossProductScale(surface);
  TriangleMesh mesh;
  mesh.positions.resize(vertexCount);
  mesh.normals.resize(vertexCount);
  // Unit normals in double; a zero vector marks a vertex where no limit normal was found.
  std::vector<Eigen::Vector3d> normals(vertexCount, Eigen::Vector3d::Zero());
  tbb::parallel_for(tbb::blocked_range<int>(0, samplesU), [&](const tbb::blocked_range<int>& rows) {
    for (int i = rows.begin(); i < rows.end(); ++i) {
      const double u = gridParameter(surface.domainU(), surface.isClosedU(), samplesU, i);
      for (int j = 0; j < samplesV; ++j) {
        const double v = gridParameter(surface.domainV(), surface.isClosedV(), samplesV, j);
        const std::size_t index = static_cast<std::size_t>(i) * samplesV + j;
        mesh.positions[index] = surface.evaluate(u, v).cast<float>();
        normals[index] = unitNormal(surface, u, v, scale);
        if (normals[index].isZero(0.0)) normals[index] = limitNormal(surface, u, v, scale);
      }
    }
  });

  const int cellsU = surface.isClosedU() ? samplesU : samplesU - 1;
  const int cellsV = surface.isClosedV() ? samplesV : samplesV - 1;
  mesh.triangles.reserve(2 * static_cast<std::size_t>(cellsU) * cellsV);
  auto vertex = [&](int i, int j) {
    return static_cast<TriangleMesh::Index>((i % samplesU) * samplesV + (j % samplesV));
  };
  for (int i = 0; i < cellsU; ++i) {
    for (int j = 0; j < cellsV; ++j) {
      const TriangleMesh::Index a = vertex(i, j);
      const TriangleMesh::Index b = vertex(i + 1, j);
      const TriangleMesh::Index c = vertex(i + 1, j + 1);
      const TriangleMesh::Index d = vertex(i, j + 1);
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  }

  // Normals for degenerate vertices: the area-weighted sum of the adjacent triangles' normals.
  std::vector<Eigen::Vector3d> fallback(vertexCount, Eigen::Vector3d::Zero());
  bool anyDegenerate = false;
  for (const Eigen::Vector3d& normal : normals) anyDegenerate = anyDegenerate || normal.isZero(0.0);
  if (anyDegenerate) {
    for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
      const Eigen::Vector3d p0 = mesh.positions[triangle[0]].cast<double>();
      const Eigen::Vector3d p1 = mesh.positions[triangle[1]].cast<double>();
      const Eigen::Vector3d p2 = mesh.positions[triangle[2]].cast<double>();
      const Eigen::Vector3d areaNormal = (p1 - p0).cross(p2 - p0);
      for (const TriangleMesh::Index index : triangle) fallback[index] += areaNormal;
    }
  }
  for (std::size_t index = 0; index < vertexCount; ++index) {
    Eigen::Vector3d normal = normals[index];
    if (normal.isZero(0.0)) {
      if (fallback[index].isZero(0.0)) {
        throw InputError("tessellate: the surface is degenerate at grid vertex (" +
                         std::to_string(index / samplesV) + ", " +
                         std::to_string(index % samplesV) +
                         "): neither Su x Sv nor the adjacent triangles define a normal");
      }
      normal = fallback[index].normalized();
    }
    mesh.normals[index] = normal.cast<float>();
  }
  return mesh;
}

}  // namespace d2vdb
