#include "d2vdb/support/SphericalTriangulation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "d2vdb/core/Error.h"

namespace d2vdb {

SphericalTriangulation geodesicSphere(int subdivisions) {
  if (subdivisions < 0 || subdivisions > 9) {
    throw InputError("geodesic sphere subdivisions " + std::to_string(subdivisions) +
                     " out of range (expected 0 to 9)");
  }
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  SphericalTriangulation sphere;
  sphere.normals = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Eigen::Vector3d& n : sphere.normals) n.normalize();
  sphere.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                      {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                      {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                      {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<SphericalTriangulation::Index, SphericalTriangulation::Index>,
             SphericalTriangulation::Index>
        midpoints;
    const auto midpoint = [&](SphericalTriangulation::Index a, SphericalTriangulation::Index b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      sphere.normals.push_back((sphere.normals[a] + sphere.normals[b]).normalized());
      const auto index = static_cast<SphericalTriangulation::Index>(sphere.normals.size() - 1);
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<SphericalTriangulation::Triangle> finer;
    finer.reserve(sphere.triangles.size() * 4);
    for (const SphericalTriangulation::Triangle& tri : sphere.triangles) {
      const auto ab = midpoint(tri[0], tri[1]);
      const auto bc = midpoint(tri[1], tri[2]);
      const auto ca = midpoint(tri[2], tri[0]);
      finer.push_back({tri[0], ab, ca});
      finer.push_back({tri[1], bc, ab});
      finer.push_back({tri[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    sphere.triangles = std::move(finer);
  }
  return sphere;
}

int geodesicSubdivisionsForSpacing(double angle) {
  if (!(angle > 0.0) || !std::isfinite(angle)) {
    throw InputError("the spacing of a geodesic sphere must be a positive angle");
  }
  // The icosahedron's edge subtends 1.107 rad; the longest edge of subdivision s stays below
  // 1.2 / 2^s (midpoint projection lengthens the central edges slightly).
  int subdivisions = 0;
  while (subdivisions < 9 && 1.2 / std::ldexp(1.0, subdivisions) > angle) ++subdivisions;
  return subdivisions;
}

Eigen::Vector3d unitNormalOrThrow(const Eigen::Vector3d& vector, const std::string& what) {
  if (!vector.allFinite()) throw InputError(what + " is not finite");
  // Scaled by the largest component first, so that neither tiny nor huge vectors lose their
  // direction to underflow or overflow in the norm.
  const double largest = vector.cwiseAbs().maxCoeff();
  if (!(largest > 1e-150)) throw InputError(what + " is zero (a normal needs a direction)");
  const Eigen::Vector3d scaled = vector / largest;
  return scaled / scaled.norm();
}

void validateSphericalTriangulation(SphericalTriangulation& domain, const std::string& what) {
  if (domain.triangles.empty()) throw InputError(what + " has no triangles");
  for (std::size_t i = 0; i < domain.normals.size(); ++i) {
    Eigen::Vector3d& n = domain.normals[i];
    const double length = n.norm();
    if (std::isfinite(length) && std::abs(length - 1.0) <= 1e-9) {
      n /= length;
    } else {
      n = unitNormalOrThrow(n, what + " normal " + std::to_string(i));
    }
  }
  const auto count = domain.normals.size();
  for (std::size_t t = 0; t < domain.triangles.size(); ++t) {
    const auto& tri = domain.triangles[t];
    for (const auto index : tri) {
      if (index >= count) {
        throw InputError(what + " triangle " + std::to_string(t) + " refers to normal " +
                         std::to_string(index) + " but there are only " + std::to_string(count));
      }
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
      throw InputError(what + " triangle " + std::to_string(t) + " repeats a corner");
    }
  }
}

bool coversWholeSphere(const SphericalTriangulation& domain) {
  std::map<std::pair<SphericalTriangulation::Index, SphericalTriangulation::Index>, int> edges;
  std::set<SphericalTriangulation::Index> used;
  for (const auto& tri : domain.triangles) {
    for (int k = 0; k < 3; ++k) {
      used.insert(tri[static_cast<std::size_t>(k)]);
      ++edges[std::minmax(tri[static_cast<std::size_t>(k)],
                          tri[static_cast<std::size_t>((k + 1) % 3)])];
    }
  }
  for (const auto& edge : edges) {
    if (edge.second != 2) return false;
  }
  const long long euler = static_cast<long long>(used.size()) -
                          static_cast<long long>(edges.size()) +
                          static_cast<long long>(domain.triangles.size());
  return euler == 2;
}

}  // namespace d2vdb
