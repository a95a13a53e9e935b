#include "d2vdb/field/SmoothSurfaceField.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/SmoothSurface.h"
#include "d2vdb/field/detail/NearestPointTree.h"
#include "d2vdb/manifold/SourceDistance.h"

namespace d2vdb {
namespace {

using Index = HalfEdgeMesh::Index;

/// Largest distance between neighbouring lattice points of one face (positions in faceLattice
/// order for `intervals` intervals per edge).
double largestLatticeStep(const std::vector<Eigen::Vector3d>& points, long intervals) {
  double largest = 0.0;
  std::size_t index = 0;
  std::vector<std::size_t> rowStart;
  for (long i = 0; i <= intervals; ++i) {
    rowStart.push_back(index);
    index += static_cast<std::size_t>(intervals - i + 1);
  }
  const auto at = [&](long i, long j) { return points[rowStart[i] + static_cast<std::size_t>(j)]; };
  for (long i = 0; i <= intervals; ++i) {
    for (long j = 0; i + j <= intervals; ++j) {
      if (i + j < intervals) {
        largest = std::max(largest, (at(i + 1, j) - at(i, j)).norm());
        largest = std::max(largest, (at(i, j + 1) - at(i, j)).norm());
      }
      if (i > 0 && i + j <= intervals) {
        largest = std::max(largest, (at(i - 1, j + 1) - at(i, j)).norm());
      }
    }
  }
  return largest;
}

}  // namespace

ApproximantField smoothSurfaceField(const PseudoManifold& surface, double voxelSize,
                                    double halfWidth, const std::string& label,
                                    const ApproximantFieldOptions& options,
                                    const ProgressCallback& progress) {
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize)) {
    throw InputError("smooth-surface field: the voxel size must be a positive number");
  }
  if (!(halfWidth >= 1.0 && halfWidth <= 64.0)) {
    throw InputError("smooth-surface field: the half-width must lie in 1..64 voxels");
  }
  const HalfEdgeMesh& mesh = surface.mesh();
  const std::size_t faceCount = mesh.faceCount();
  const double spacing = 0.8 * voxelSize;
  const double seedBudget = 4.0 * static_cast<double>(options.maxActiveVoxels);

  // Intervals per face edge from the mesh's edge lengths, then doubled until neighbouring seeds
  // on the surface lie within `spacing`.
  std::vector<long> intervals(faceCount);
  tbb::parallel_for(std::size_t{0}, faceCount, [&](std::size_t f) {
    const auto face = static_cast<Index>(f);
    double extent = 0.0;
    for (int k = 0; k < 3; ++k) {
      extent = std::max(extent, (mesh.position(mesh.corner(face, k)) -
                                 mesh.position(mesh.corner(face, (k + 1) % 3)))
                                    .norm());
    }
    intervals[f] = std::max(1L, static_cast<long>(std::ceil(1.25 * extent / spacing)));
  });
  const auto seedCount = [&]() {
    double count = 0.0;
    for (const long g : intervals) count += 0.5 * static_cast<double>(g + 1) * (g + 2);
    return count;
  };
  std::vector<std::vector<Eigen::Vector3d>> facePositions(faceCount);
  std::vector<bool> done(faceCount, false);
  for (int round = 0; round < 8; ++round) {
    if (seedCount() > seedBudget) {
      throw InputError("smooth-surface field: " + std::to_string(seedCount()) +
                       " surface seeds would be needed at voxel size " + std::to_string(voxelSize) +
                       ", more than the budget of " + std::to_string(seedBudget) +
                       "; choose a coarser voxel size");
    }
    tbb::parallel_for(std::size_t{0}, faceCount, [&](std::size_t f) {
      if (done[f]) return;
      const auto face = static_cast<Index>(f);
      const std::vector<Eigen::Vector3d> lattice = faceLattice(static_cast<int>(intervals[f]));
      std::vector<Eigen::Vector3d>& points = facePositions[f];
      points.resize(lattice.size());
      for (std::size_t i = 0; i < lattice.size(); ++i)
        points[i] = surface.position({face, lattice[i]});
      if (largestLatticeStep(points, intervals[f]) <= spacing) {
        done[f] = true;
      } else {
        intervals[f] *= 2;
      }
    });
    if (std::all_of(done.begin(), done.end(), [](bool d) { return d; })) break;
  }
  if (!std::all_of(done.begin(), done.end(), [](bool d) { return d; })) {
    throw InputError("smooth-surface field: the surface could not be sampled at voxel size " +
                     std::to_string(voxelSize) + " (a face stretches too far)");
  }
  std::vector<Eigen::Vector3d> seeds;
  std::vector<FacePoint> seedPoints;
  for (std::size_t f = 0; f < faceCount; ++f) {
    const std::vector<Eigen::Vector3d> lattice = faceLattice(static_cast<int>(intervals[f]));
    for (std::size_t i = 0; i < lattice.size(); ++i) {
      seeds.push_back(facePositions[f][i]);
      seedPoints.push_back({static_cast<Index>(f), lattice[i]});
    }
    std::vector<Eigen::Vector3d>().swap(facePositions[f]);
  }
  std::vector<Eigen::Vector3f> seedFloats(seeds.size());
  for (std::size_t i = 0; i < seeds.size(); ++i) seedFloats[i] = seeds[i].cast<float>();
  const detail::NearestPointTree tree(seedFloats);

  FieldBand band =
      FieldBand::nearSeeds(TargetKind::Surface, std::move(seeds), voxelSize, halfWidth);
  const double clamp = 1.0 / voxelSize;
  band.setApproximantsPerWorker([&]() -> FieldBand::VoxelApproximant {
        // The hint only speeds up the nearest-seed search; its answer (ties to the lowest index)
        // and hence every voxel's approximant do not depend on it.
        return [&, hint = std::uint32_t{0}](const openvdb::Coord&,
                                            const Eigen::Vector3d& centre) mutable {
          const detail::NearestPointTree::Nearest nearest =
              tree.nearest(centre.cast<float>(), hint);
          hint = nearest.index;
          Approximant a = SmoothSurface::approximantOf(
              centre, surface.project(centre, seedPoints[nearest.index]));
          if (std::abs(a.k1) > clamp || std::abs(a.k2) > clamp) {
            a.k1 = std::clamp(a.k1, -clamp, clamp);
            a.k2 = std::clamp(a.k2, -clamp, clamp);
            a.flags |= kFlagCurvatureClamped;
          }
          return a;
        };
      })
      .setEstimator(std::string(kSmoothSurfaceEstimator) + ", " + surface.sourceName() + " source")
      .setLabel("smooth surface (" + surface.sourceName() + ") of " + std::to_string(faceCount) +
                " faces" + (label.empty() ? "" : " from " + label));
  return ApproximantField::fromBand(band, options, progress);
}

}  // namespace d2vdb
