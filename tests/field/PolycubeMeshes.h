// Reproducible coarse closed meshes with sharp concave corners, for the sign tests of mesh to
// level set: the boundary of a random polycube (a slab of unit cells with through-tunnels and
// notches), its lattice vertices jittered and the whole shape rotated off the voxel axes.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::test {

/// A uniform double in [low, high) from the standard-defined mt19937 sequence (the library's
/// distributions are not specified bit for bit across implementations).
inline double uniform(std::mt19937& random, double low, double high) {
  return low + (high - low) * (static_cast<double>(random()) / 4294967296.0);
}

/// What makePolycubeMesh() builds.
struct PolycubeSpec {
  int genus = 0;           ///< number of through-tunnels (each one cell wide)
  int notches = 2;         ///< cells removed from the top layer's rim or interior
  double jitter = 0.2;     ///< largest vertex displacement per axis, in cells
  double cell = 1.0;       ///< cell edge in world units
  std::uint32_t seed = 1;  ///< everything random derives from it
};

/// The polycube boundary: quads between occupied and empty cells, each split along a random
/// diagonal, wound counter-clockwise seen from outside; vertices shared through their lattice
/// coordinates. The slab is (2 * genus + 3) x 3 x 2 cells (at least 5 wide); tunnel k removes the
/// column of cells at x = 2k + 1 (then shifted in y at random), so tunnels never touch each other
/// or the rim. Notches remove top-layer cells elsewhere, but never one that would leave cells
/// touching only along an edge (which would make the boundary non-manifold): a notch is accepted
/// only when every empty top-layer cell's 2x2 neighbourhoods stay free of diagonal-only pairs.
/// The result is a closed, 2-manifold, consistently oriented mesh of genus `genus` (Euler
/// characteristic 2 - 2 genus), without self-intersections for jitter < 0.25.
inline TriangleMesh makePolycubeMesh(const PolycubeSpec& spec) {
  std::mt19937 random(spec.seed);
  const int nx = 2 * spec.genus + 3;
  const int ny = 3 + spec.genus % 2;
  const int nz = 2;
  // occupied[x][y][z]; the border of the array (index 0 and n+1) is empty space.
  std::vector<std::vector<std::vector<bool>>> occupied(
      nx + 2, std::vector<std::vector<bool>>(ny + 2, std::vector<bool>(nz + 2, false)));
  for (int x = 1; x <= nx; ++x)
    for (int y = 1; y <= ny; ++y)
      for (int z = 1; z <= nz; ++z) occupied[x][y][z] = true;
  for (int k = 0; k < spec.genus; ++k) {
    const int x = 2 * k + 2;
    const int y = 2 + static_cast<int>(random() % static_cast<std::uint32_t>(ny - 2));
    for (int z = 1; z <= nz; ++z) occupied[x][y][z] = false;
  }
  // A notch must not create a diagonal-only contact in any 2x2 block of the top layer, nor
  // between the layers (the bottom layer is full wherever the top is, except at tunnels, which
  // remove both layers).
  const auto diagonalOnly = [&](int x, int y) {  // the 2x2 block with lowest corner (x, y)
    const bool a = occupied[x][y][nz], b = occupied[x + 1][y][nz];
    const bool c = occupied[x][y + 1][nz], d = occupied[x + 1][y + 1][nz];
    return (a && d && !b && !c) || (b && c && !a && !d);
  };
  int placed = 0;
  for (int attempt = 0; attempt < 200 && placed < spec.notches; ++attempt) {
    const int x = 1 + static_cast<int>(random() % static_cast<std::uint32_t>(nx));
    const int y = 1 + static_cast<int>(random() % static_cast<std::uint32_t>(ny));
    if (!occupied[x][y][nz] || !occupied[x][y][nz - 1]) continue;
    occupied[x][y][nz] = false;
    bool fine = true;
    for (int bx = x - 1; bx <= x && fine; ++bx)
      for (int by = y - 1; by <= y && fine; ++by) fine = !diagonalOnly(bx, by);
    // The bottom cell under the notch must keep a top-layer or side neighbour above it so that
    // the notch floor is not the only contact; a notch next to a tunnel could also touch it only
    // diagonally, which the 2x2 test above covers (tunnel cells are empty in the top layer too).
    if (!fine) {
      occupied[x][y][nz] = true;
      continue;
    }
    ++placed;
  }

  TriangleMesh mesh;
  std::map<std::array<int, 3>, TriangleMesh::Index> vertexOf;
  const auto vertex = [&](int x, int y, int z) {
    const std::array<int, 3> key{x, y, z};
    const auto found = vertexOf.find(key);
    if (found != vertexOf.end()) return found->second;
    const auto index = static_cast<TriangleMesh::Index>(mesh.positions.size());
    vertexOf.emplace(key, index);
    mesh.positions.emplace_back(float(x), float(y), float(z));
    return index;
  };
  // Cell (x, y, z) spans [x-1, x] x [y-1, y] x [z-1, z] in lattice coordinates.
  const auto addQuad = [&](std::array<TriangleMesh::Index, 4> quad) {
    if (random() % 2 == 0) {
      mesh.triangles.push_back({quad[0], quad[1], quad[2]});
      mesh.triangles.push_back({quad[0], quad[2], quad[3]});
    } else {
      mesh.triangles.push_back({quad[0], quad[1], quad[3]});
      mesh.triangles.push_back({quad[1], quad[2], quad[3]});
    }
  };
  for (int x = 1; x <= nx; ++x) {
    for (int y = 1; y <= ny; ++y) {
      for (int z = 1; z <= nz; ++z) {
        if (!occupied[x][y][z]) continue;
        const int x0 = x - 1, y0 = y - 1, z0 = z - 1;
        if (!occupied[x - 1][y][z])
          addQuad({vertex(x0, y0, z0), vertex(x0, y0, z), vertex(x0, y, z), vertex(x0, y, z0)});
        if (!occupied[x + 1][y][z])
          addQuad({vertex(x, y0, z0), vertex(x, y, z0), vertex(x, y, z), vertex(x, y0, z)});
        if (!occupied[x][y - 1][z])
          addQuad({vertex(x0, y0, z0), vertex(x, y0, z0), vertex(x, y0, z), vertex(x0, y0, z)});
        if (!occupied[x][y + 1][z])
          addQuad({vertex(x0, y, z0), vertex(x0, y, z), vertex(x, y, z), vertex(x, y, z0)});
        if (!occupied[x][y][z - 1])
          addQuad({vertex(x0, y0, z0), vertex(x0, y, z0), vertex(x, y, z0), vertex(x, y0, z0)});
        if (!occupied[x][y][z + 1])
          addQuad({vertex(x0, y0, z), vertex(x, y0, z), vertex(x, y, z), vertex(x0, y, z)});
      }
    }
  }
  // Jitter, rotate about a random axis, scale and move off the origin.
  const Eigen::Vector3d axis =
      Eigen::Vector3d(uniform(random, -1, 1), uniform(random, -1, 1), uniform(random, 0.2, 1))
          .normalized();
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(uniform(random, 0.3, 2.8), axis).toRotationMatrix();
  const Eigen::Vector3d offset(uniform(random, -0.5, 0.5), uniform(random, -0.5, 0.5),
                               uniform(random, -0.5, 0.5));
  for (Eigen::Vector3f& p : mesh.positions) {
    Eigen::Vector3d q = p.cast<double>();
    for (int axisIndex = 0; axisIndex < 3; ++axisIndex) {
      q[axisIndex] += uniform(random, -spec.jitter, spec.jitter);
    }
    p = (spec.cell * (rotation * q) + offset).cast<float>();
  }
  return mesh;
}

}  // namespace d2vdb::test
