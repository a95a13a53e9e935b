// Option groups several sub-commands share, each declared by one function with one set of help
// texts and defaults: the voxel size of a narrow band (--voxel-size, --resolution, --half-width,
// --max-voxels) and how a .vdb file is written (--half, --no-compression).
#pragma once

#include <CLI/CLI.hpp>

#include <Eigen/Geometry>

#include <cstdint>
#include <string>

#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/field/VoxelBudget.h"
#include "d2vdb/io/VdbFile.h"

namespace d2vdb::cli {

/// The band options: a voxel size given directly, or as voxels along the target's longest side.
struct BandArguments {
  double voxelSize = 0;  ///< world units; 0 = from `resolution`
  int resolution = 0;    ///< voxels along the longest side; 0 = kDefaultResolution
  double halfWidth = 3;  ///< voxels on each side of the surface
  std::uint64_t maxVoxels = kDefaultMaxActiveVoxels;

  /// The resolution in force: `resolution`, or kDefaultResolution when it was not given.
  int resolutionOrDefault() const { return resolution > 0 ? resolution : kDefaultResolution; }
  /// The voxel size for a target with bounding box `bounds`: `voxelSize` when given, else the
  /// longest side over resolutionOrDefault(). Throws InputError (naming `what`) when the box has
  /// no extent and no voxel size was given.
  double voxelSizeFor(const Eigen::AlignedBox3d& bounds, const std::string& what) const;
  /// The level-set options of these arguments (the voxel size or the resolution in force), with
  /// the memory budget of --max-memory.
  LevelSetOptions levelSetOptions(const ResourceBudget& budget) const;
};

/// Help texts of the band options that differ between sub-commands.
struct BandOptionHelp {
  std::string target = "the target";  ///< what --resolution measures, e.g. "the mesh"
  std::string prefix;                 ///< prefixed to every help text, e.g. "levelset outputs: "
};

/// Declares --voxel-size, --resolution (default kDefaultResolution), --half-width and
/// --max-voxels into `band`; --voxel-size and --resolution exclude each other.
void declareBandOptions(CLI::App& command, BandArguments& band, const BandOptionHelp& help = {});

/// How .vdb outputs are written.
struct VdbOutputArguments {
  bool half = false;           ///< 16-bit half floats
  bool noCompression = false;  ///< no Blosc

  /// The write options of these arguments, with `source` and `halfWidth` metadata (VdbFile.h).
  VdbWriteOptions writeOptions(const std::string& source, double halfWidth = 0) const;
};

/// Declares --half and --no-compression into `output`.
void declareVdbOutputOptions(CLI::App& command, VdbOutputArguments& output);

}  // namespace d2vdb::cli
