// Estimating the size of a narrow-band level set before building it, and refusing requests that
// would exhaust memory.
#pragma once

#include <cstdint>
#include <string>

namespace d2vdb {

/// Default limit on the active voxels of one level set, sized for a 24 GiB machine.
/// Measured (getrusage peak-RSS increase during meshToLevelSet of an 81920-triangle icosphere,
/// half-width 3, 2 threads, 7.5e5 to 4.8e7 active voxels): 37 bytes per active voxel at every
/// size; the finished FloatGrid keeps 12 bytes per active voxel (4-byte values in 8^3 leaves that
/// are about a third full). The pipeline then adds approximant grids sharing the level set's
/// topology (normal or footpoint, k1, k2, e1: 8 float channels, about 96 bytes per voxel at the
/// same fill ratio). At 1.5e8 voxels: conversion peak 5.2 GiB, level set plus approximants
/// 1.5e8 * 108 B = 15 GiB, leaving the rest of 24 GiB to the OS, the input and output buffers.
/// That is a surface of about 2e7 voxel faces (a sphere of radius ~1260 voxels) at half-width 3.
inline constexpr std::uint64_t kDefaultMaxActiveVoxels = 150'000'000;

/// Factor applied to the flat-band voxel count. The band of a flat surface of area A holds exactly
/// A / voxelSize^2 * 2 * halfWidth voxel centres; curvature adds a relative
/// (halfWidth * voxelSize * k)^2 / 3 for a sphere of curvature k, convex edges and corners add a
/// wedge of relative size ~halfWidth * voxelSize / (feature size), and OpenVDB's mesh band can be
/// a fraction of a voxel wider than asked. 1.25 covers features down to ~1.2 band widths; thinner
/// or overlapping features have overlapping bands and fewer voxels than estimated.
inline constexpr double kActiveVoxelSafetyFactor = 1.25;

/// Estimated active voxel count of a narrow band of `halfWidth` voxels on each side of a surface
/// of `surfaceArea` world units squared, at `voxelSize` world units:
/// area / voxelSize^2 * 2 * halfWidth * kActiveVoxelSafetyFactor. A double because absurd requests
/// exceed 2^64; returns +inf for a non-positive voxel size.
double estimateActiveVoxels(double surfaceArea, double voxelSize, double halfWidth);

/// The smallest voxel size whose estimate stays within `maxActiveVoxels` (world units);
/// the inverse of estimateActiveVoxels.
double smallestVoxelSizeWithinBudget(double surfaceArea, double halfWidth,
                                     std::uint64_t maxActiveVoxels);

/// What a level-set builder is about to allocate; see enforceVoxelBudget().
struct VoxelBudgetRequest {
  std::string subject;     ///< what is converted, for the message, e.g. "mesh (12 triangles)"
  double surfaceArea = 0;  ///< world units squared
  double voxelSize = 0;    ///< world units
  double halfWidth = 3;    ///< voxels on each side of the surface
  double longestSide = 0;  ///< longest bounding-box side (world); 0 = unknown (no resolution hint)
  std::uint64_t maxActiveVoxels = kDefaultMaxActiveVoxels;
};

/// Throws InputError when the estimate exceeds the limit, before anything is allocated. The
/// message states the estimate, the limit, and the smallest voxel size (and, when the longest side
/// is known, the largest resolution along it) that would fit.
void enforceVoxelBudget(const VoxelBudgetRequest& request);

}  // namespace d2vdb
