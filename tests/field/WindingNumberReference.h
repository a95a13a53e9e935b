// Brute-force generalised winding numbers, the independent reference of the sign tests: the sum
// of every triangle's signed solid angle (the arctangent formula of Van Oosterom and Strackee,
// IEEE Trans. Biomedical Engineering 30(2), 1983), divided by 4 pi. Double precision on the
// mesh's float coordinates; O(triangles) per point.
#pragma once

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::test {

/// The mesh's triangles as double corner triples, for fast repeated sums.
class WindingNumberReference {
 public:
  explicit WindingNumberReference(const TriangleMesh& mesh) {
    for (const TriangleMesh::Triangle& t : mesh.triangles) {
      corners_.push_back({mesh.positions[t[0]].cast<double>(), mesh.positions[t[1]].cast<double>(),
                          mesh.positions[t[2]].cast<double>()});
    }
  }

  /// w(q): 1 inside a closed outward-wound mesh, 0 outside.
  double operator()(const Eigen::Vector3d& q) const {
    double sum = 0.0;
    for (const auto& c : corners_) {
      const Eigen::Vector3d a = c[0] - q;
      const Eigen::Vector3d b = c[1] - q;
      const Eigen::Vector3d d = c[2] - q;
      const double la = a.norm(), lb = b.norm(), ld = d.norm();
      const double triple = a.dot(b.cross(d));
      const double denominator = la * lb * ld + a.dot(b) * ld + b.dot(d) * la + d.dot(a) * lb;
      sum += 2.0 * std::atan2(triple, denominator);
    }
    return sum / (4.0 * M_PI);
  }

 private:
  std::vector<std::array<Eigen::Vector3d, 3>> corners_;
};

/// What compareSignsWithWindingNumbers() counted.
struct SignCheck {
  std::size_t checked = 0;
  std::size_t wrong = 0;
};

/// Compares the sign of every active voxel of `grid` (inside when negative) with w >= 1/2 at its
/// centre, in parallel. Voxels whose |value| is below `skipBelow` (world units) are left out:
/// centres that close to the surface may take either side (their value is their exact distance
/// to the mesh there), and float rounding of the two computations differs at that scale.
/// `keep` (optional) selects voxels to check.
inline SignCheck compareSignsWithWindingNumbers(
    const openvdb::FloatGrid& grid, const WindingNumberReference& winding, double skipBelow,
    const std::function<bool(const openvdb::Coord&)>& keep = {}) {
  std::vector<std::pair<openvdb::Coord, float>> voxels;
  for (auto voxel = grid.cbeginValueOn(); voxel; ++voxel) {
    if (std::abs(*voxel) < skipBelow) continue;
    if (keep && !keep(voxel.getCoord())) continue;
    voxels.emplace_back(voxel.getCoord(), *voxel);
  }
  const std::size_t wrong = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, voxels.size(), 64), std::size_t{0},
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t count) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const openvdb::Vec3d w = grid.indexToWorld(voxels[i].first);
          const bool inside = winding(Eigen::Vector3d(w.x(), w.y(), w.z())) >= 0.5;
          if (inside != (voxels[i].second < 0.0f)) ++count;
        }
        return count;
      },
      std::plus<>());
  return {voxels.size(), wrong};
}

}  // namespace d2vdb::test
