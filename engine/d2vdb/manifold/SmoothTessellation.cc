#include "d2vdb/manifold/SmoothTessellation.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"

namespace d2vdb {

using Index = HalfEdgeMesh::Index;

std::size_t smoothTessellationTriangles(const HalfEdgeMesh& mesh, int levels) {
  const std::size_t perFace = std::size_t{1} << (2 * levels);
  if (mesh.faceCount() > std::numeric_limits<std::size_t>::max() / perFace) {
    return std::numeric_limits<std::size_t>::max();
  }
  return mesh.faceCount() * perFace;
}

double smoothTessellationVertices(const HalfEdgeMesh& mesh, int levels) {
  const double g = std::ldexp(1.0, levels);  // intervals per edge
  double used = 0.0;
  for (Index v = 0; v < mesh.vertexCount(); ++v) used += mesh.degree(v) > 0 ? 1.0 : 0.0;
  const double edges = 0.5 * static_cast<double>(mesh.halfEdgeCount());
  return used + edges * (g - 1.0) +
         static_cast<double>(mesh.faceCount()) * (g - 1.0) * (g - 2.0) / 2.0;
}

namespace {

double smoothFileBytes(const HalfEdgeMesh& mesh, int levels, bool curvature, MeshFormat format) {
  MeshFileContents contents;
  contents.normals = true;
  contents.colors = curvature;
  contents.scalars = curvature ? 2 : 0;
  return estimateMeshFileBytes(format, smoothTessellationVertices(mesh, levels),
                               std::ldexp(static_cast<double>(mesh.faceCount()), 2 * levels),
                               contents);
}

}  // namespace

double estimateSmoothTessellationMemoryBytes(const HalfEdgeMesh& mesh, int levels, bool curvature) {
  const double perVertex = 32.0 + 24.0 + (curvature ? 51.0 : 0.0) + 24.0;
  return perVertex * smoothTessellationVertices(mesh, levels);
}

void enforceSmoothTessellationBudget(const HalfEdgeMesh& mesh, int levels, bool curvature,
                                     MeshFormat format, const ResourceBudget& budget) {
  const auto fits = [&](long long level) {
    const int l = static_cast<int>(level);
    return (budget.maxMemoryBytes == 0 ||
            estimateSmoothTessellationMemoryBytes(mesh, l, curvature) <=
                static_cast<double>(budget.maxMemoryBytes)) &&
           (budget.maxOutputBytes == 0 || smoothFileBytes(mesh, l, curvature, format) <=
                                              static_cast<double>(budget.maxOutputBytes));
  };
  if (fits(levels)) return;
  const long long fitting = largestFitting(0, levels, fits);
  BudgetRequest request;
  request.subject = "level of detail " + std::to_string(levels) + " (--lod) of " +
                    std::to_string(mesh.faceCount()) + " faces, " +
                    std::to_string(static_cast<long long>(
                        std::ldexp(static_cast<double>(mesh.faceCount()), 2 * levels))) +
                    " triangles in " + meshFormatName(format);
  request.remedy =
      fitting >= 0 ? "use --lod " + std::to_string(fitting) + " or lower" : "use a smaller mesh";
  request.estimatedBytes = smoothFileBytes(mesh, levels, curvature, format);
  enforceOutputBudget(request, budget);
  request.estimatedBytes = estimateSmoothTessellationMemoryBytes(mesh, levels, curvature);
  enforceMemoryBudget(request, budget);
}

void checkSmoothTessellation(const HalfEdgeMesh& mesh, int levels, std::size_t maxTriangles) {
  if (levels < 0 || levels > 10) {
    throw InputError("the level of detail must lie in 0..10, not " + std::to_string(levels));
  }
  const std::size_t triangleCount = smoothTessellationTriangles(mesh, levels);
  if (triangleCount > maxTriangles ||
      triangleCount > std::numeric_limits<TriangleMesh::Index>::max()) {
    throw InputError("level of detail " + std::to_string(levels) + " would make " +
                     std::to_string(triangleCount) + " triangles (" +
                     std::to_string(mesh.faceCount()) + " faces x 4^" + std::to_string(levels) +
                     "), more than the limit of " + std::to_string(maxTriangles) +
                     "; choose a lower level");
  }
}

SmoothTessellation tessellateSmooth(const PseudoManifold& surface, int levels, bool curvature,
                                    std::size_t maxTriangles) {
  const HalfEdgeMesh& mesh = surface.mesh();
  checkSmoothTessellation(mesh, levels, maxTriangles);
  const std::size_t triangleCount = smoothTessellationTriangles(mesh, levels);
  const long g = 1L << levels;  // intervals per edge
  const std::size_t edgeInterior = static_cast<std::size_t>(g - 1);
  const std::size_t faceInterior = static_cast<std::size_t>((g - 1) * (g - 2) / 2);

  // Vertex numbering: used mesh vertices, then edge points, then face interiors.
  std::vector<Index> vertexIndex(mesh.vertexCount(), std::numeric_limits<Index>::max());
  std::vector<FacePoint> where;
  for (Index v = 0; v < mesh.vertexCount(); ++v) {
    if (mesh.degree(v) == 0) continue;
    vertexIndex[v] = static_cast<Index>(where.size());
    const Index h = mesh.ring(v, 0);
    FacePoint p{HalfEdgeMesh::face(h), Eigen::Vector3d::Zero()};
    p.bary[h % 3] = 1.0;
    where.push_back(p);
  }
  std::vector<Index> edgeOf(mesh.halfEdgeCount());
  std::vector<Index> canonical;  // the smaller half-edge of each edge
  for (Index h = 0; h < mesh.halfEdgeCount(); ++h) {
    if (h < mesh.twin(h)) {
      edgeOf[h] = edgeOf[mesh.twin(h)] = static_cast<Index>(canonical.size());
      canonical.push_back(h);
    }
  }
  const std::size_t edgeBase = where.size();
  const std::size_t faceBase = edgeBase + canonical.size() * edgeInterior;
  const std::size_t vertexCount = faceBase + mesh.faceCount() * faceInterior;
  if (vertexCount > std::numeric_limits<Index>::max()) {
    throw InputError("level of detail " + std::to_string(levels) +
                     " would need more than 2^32 vertices");
  }
  where.resize(vertexCount);
  const double step = 1.0 / static_cast<double>(g);
  tbb::parallel_for(std::size_t{0}, canonical.size(), [&](std::size_t e) {
    const Index h = canonical[e];
    for (long m = 1; m < g; ++m) {
      FacePoint p{HalfEdgeMesh::face(h), Eigen::Vector3d::Zero()};
      p.bary[h % 3] = static_cast<double>(g - m) * step;
      p.bary[(h + 1) % 3] = static_cast<double>(m) * step;
      where[edgeBase + e * edgeInterior + static_cast<std::size_t>(m - 1)] = p;
    }
  });
  tbb::parallel_for(std::size_t{0}, mesh.faceCount(), [&](std::size_t f) {
    std::size_t local = 0;
    for (long i = 1; i < g; ++i) {
      for (long j = 1; i + j < g; ++j) {
        where[faceBase + f * faceInterior + local++] = {
            static_cast<Index>(f),
            Eigen::Vector3d(static_cast<double>(g - i - j) * step, static_cast<double>(i) * step,
                            static_cast<double>(j) * step)};
      }
    }
  });

  SmoothTessellation result;
  const std::vector<SmoothPoint> points =
      surface.evaluate(where, curvature ? Derivatives::Second : Derivatives::First);
  result.mesh.positions.resize(vertexCount);
  result.mesh.normals.resize(vertexCount);
  if (curvature) {
    result.k1.resize(vertexCount);
    result.k2.resize(vertexCount);
    result.e1.resize(vertexCount);
  }
  tbb::parallel_for(std::size_t{0}, vertexCount, [&](std::size_t i) {
    result.mesh.positions[i] = points[i].position.cast<float>();
    result.mesh.normals[i] = points[i].normal.cast<float>();
    if (curvature) {
      result.k1[i] = points[i].k1;
      result.k2[i] = points[i].k2;
      result.e1[i] = points[i].e1;
    }
  });

  // Triangles: lattice point (i, j) of face f (b1 = i / g, b2 = j / g) to its shared vertex.
  result.mesh.triangles.resize(triangleCount);
  tbb::parallel_for(std::size_t{0}, mesh.faceCount(), [&](std::size_t f) {
    const auto face = static_cast<Index>(f);
    const auto edgePoint = [&](int side, long m) {  // m-th point from corner `side`
      const Index h = 3 * face + static_cast<Index>(side);
      const Index e = edgeOf[h];
      const long along = h == canonical[e] ? m : g - m;
      return static_cast<Index>(edgeBase + e * edgeInterior + static_cast<std::size_t>(along - 1));
    };
    const auto index = [&](long i, long j) -> Index {
      const long k = g - i - j;  // lattice coordinate along b0
      if (i == 0 && j == 0) return vertexIndex[mesh.corner(face, 0)];
      if (i == g) return vertexIndex[mesh.corner(face, 1)];
      if (j == g) return vertexIndex[mesh.corner(face, 2)];
      if (j == 0) return edgePoint(0, i);  // corner 0 -> 1
      if (k == 0) return edgePoint(1, j);  // corner 1 -> 2
      if (i == 0) return edgePoint(2, k);  // corner 2 -> 0
      // Interior: same order as above (i outer, j inner).
      const std::size_t before =
          static_cast<std::size_t>((i - 1) * (g - 2) - (i - 1) * (i - 2) / 2);
      return static_cast<Index>(faceBase + f * faceInterior + before +
                                static_cast<std::size_t>(j - 1));
    };
    std::size_t t = f * static_cast<std::size_t>(g * g);
    for (long i = 0; i < g; ++i) {
      for (long j = 0; i + j < g; ++j) {
        result.mesh.triangles[t++] = {index(i, j), index(i + 1, j), index(i, j + 1)};
        if (i + j + 1 < g) {
          result.mesh.triangles[t++] = {index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)};
        }
      }
    }
  });
  result.where = std::move(where);
  return result;
}

}  // namespace d2vdb
