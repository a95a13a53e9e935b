#include "SharedOptions.h"

#include <cctype>

#include "Command.h"
#include "d2vdb/core/Error.h"

namespace d2vdb::cli {

double BandArguments::voxelSizeFor(const Eigen::AlignedBox3d& bounds,
                                   const std::string& what) const {
  return voxelSizeForBox(bounds.sizes().maxCoeff(), voxelSize, resolutionOrDefault(), what);
}

LevelSetOptions BandArguments::levelSetOptions(const ResourceBudget& budget) const {
  LevelSetOptions options;
  options.voxelSize = voxelSize;
  options.resolution = voxelSize > 0 ? 0 : resolutionOrDefault();
  options.halfWidth = halfWidth;
  options.maxActiveVoxels = maxVoxels;
  options.maxMemoryBytes = budget.maxMemoryBytes;
  return options;
}

namespace {

// "Voxel edge length", or with a prefix "levelset outputs: voxel edge length".
std::string helpText(const BandOptionHelp& help, std::string text) {
  if (help.prefix.empty()) {
    text.front() = static_cast<char>(std::toupper(static_cast<unsigned char>(text.front())));
    return text;
  }
  return help.prefix + text;
}

}  // namespace

void declareBandOptions(CLI::App& command, BandArguments& band, const BandOptionHelp& help) {
  auto* voxelSize = command.add_option("--voxel-size", band.voxelSize,
                                       helpText(help, "voxel edge length in world units"));
  auto* resolution =
      command.add_option("--resolution", band.resolution,
                         helpText(help, "voxels along the longest side of " + help.target +
                                            "'s bounding box (instead of --voxel-size; default " +
                                            std::to_string(kDefaultResolution) + ")"));
  voxelSize->excludes(resolution)->check(positiveNumber());
  resolution->excludes(voxelSize)->check(positiveNumber());
  command
      .add_option("--half-width", band.halfWidth,
                  helpText(help, "narrow-band half-width in voxels"))
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  command
      .add_option("--max-voxels", band.maxVoxels,
                  helpText(help, "refuse when the estimated number of active voxels exceeds this"))
      ->capture_default_str();
}

VdbWriteOptions VdbOutputArguments::writeOptions(const std::string& source,
                                                 double halfWidth) const {
  VdbWriteOptions options;
  options.blosc = !noCompression;
  options.halfFloat = half;
  options.source = source;
  options.halfWidth = halfWidth;
  return options;
}

void declareVdbOutputOptions(CLI::App& command, VdbOutputArguments& output) {
  command.add_flag("--half", output.half, "Store values as 16-bit half floats (smaller, lossy)");
  command.add_flag("--no-compression", output.noCompression, "Write without Blosc compression");
}

}  // namespace d2vdb::cli
