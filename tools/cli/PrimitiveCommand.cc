// d2vdb primitive: narrow-band level set of an analytic shape with exact signed distances.
#include <memory>
#include <string>
#include <vector>

#include "Command.h"
#include "SharedOptions.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/VdbFile.h"

namespace d2vdb::cli {
namespace {

struct PrimitiveArguments {
  std::string shape, output, gridName = "surface";
  std::array<double, 3> center{0, 0, 0}, min{-1, -1, -1}, max{1, 1, 1};
  double radius = 1, majorRadius = 1, minorRadius = 0.25, height = 2;
  BandArguments band;
  VdbOutputArguments vdb;
};

Eigen::Vector3d toEigen(const std::array<double, 3>& value) {
  return {value[0], value[1], value[2]};
}

std::unique_ptr<AnalyticShape> makeShape(const PrimitiveArguments& args,
                                         const CommandContext& command) {
  // Options that belong to another shape are a usage error rather than silently ignored.
  const auto reject = [&command, &args](std::initializer_list<const char*> names) {
    for (const char* name : names) {
      if (command.count(name) > 0) {
        throw CLI::ValidationError(name, "does not apply to a " + args.shape);
      }
    }
  };
  if (args.shape == "sphere") {
    reject({"--min", "--max", "--major", "--minor", "--height"});
    return std::make_unique<Sphere>(toEigen(args.center), args.radius);
  }
  if (args.shape == "box") {
    reject({"--center", "--radius", "--major", "--minor", "--height"});
    return std::make_unique<Box>(toEigen(args.min), toEigen(args.max));
  }
  if (args.shape == "torus") {
    reject({"--min", "--max", "--radius", "--height"});
    return std::make_unique<Torus>(toEigen(args.center), args.majorRadius, args.minorRadius);
  }
  reject({"--min", "--max", "--major", "--minor"});
  return std::make_unique<CappedCylinder>(toEigen(args.center), args.radius, args.height);
}

void declarePrimitive(CLI::App& command, PrimitiveArguments& args) {
  command.add_option("shape", args.shape, "sphere, box, torus or cylinder")
      ->required()
      ->check(CLI::IsMember({"sphere", "box", "torus", "cylinder"}));
  command.add_option("output", args.output, "Output .vdb file (written atomically)")->required();
  addVector3Option(command, "--center", args.center, "Centre (sphere, torus, cylinder)")
      ->default_str("0,0,0");
  addVector3Option(command, "--min", args.min, "Minimum corner (box)")->default_str("-1,-1,-1");
  addVector3Option(command, "--max", args.max, "Maximum corner (box)")->default_str("1,1,1");
  command.add_option("--radius", args.radius, "Radius (sphere, cylinder)")->capture_default_str();
  command.add_option("--major", args.majorRadius, "Major radius (torus)")->capture_default_str();
  command.add_option("--minor", args.minorRadius, "Minor (tube) radius (torus)")
      ->capture_default_str();
  command.add_option("--height", args.height, "Height (cylinder)")->capture_default_str();
  declareBandOptions(command, args.band, {"the shape", ""});
  command.add_option("--name", args.gridName, "Name of the written grid")->capture_default_str();
  declareVdbOutputOptions(command, args.vdb);
}

Report runPrimitive(const PrimitiveArguments& args, const CommandContext& context) {
  const Stopwatch clock;
  const std::unique_ptr<AnalyticShape> shape = makeShape(args, context);
  const Eigen::AlignedBox3d bounds = shape->bounds();
  PrimitiveLevelSetOptions levelSet;
  levelSet.voxelSize = args.band.voxelSizeFor(bounds, "shape");
  levelSet.halfWidth = args.band.halfWidth;
  levelSet.maxActiveVoxels = args.band.maxVoxels;
  levelSet.maxMemoryBytes = context.options().budget.maxMemoryBytes;
  const openvdb::FloatGrid::Ptr grid = primitiveLevelSet(*shape, levelSet);
  checkResolvesShape(*grid, bounds.sizes().maxCoeff(), "the shape");
  grid->setName(args.gridName);
  writeVdb(args.output, {grid}, args.vdb.writeOptions(shape->describe(), levelSet.halfWidth));
  Report report;
  report.json = {{"shape", args.shape},
                 {"description", shape->describe()},
                 {"output", args.output},
                 {"voxel_size", levelSet.voxelSize},
                 {"half_width", levelSet.halfWidth},
                 {"active_voxels", grid->activeVoxelCount()},
                 {"seconds", clock.seconds()}};
  report.text = "wrote " + args.output + ": " + shape->describe() + ", " +
                std::to_string(grid->activeVoxelCount()) + " active voxels, voxel size " +
                std::to_string(levelSet.voxelSize) + ", " + std::to_string(clock.seconds()) +
                " s\n";
  return report;
}

std::vector<OutputFile> outputsOfPrimitive(const PrimitiveArguments& args) {
  return {{"output", args.output, OutputFormat::Vdb}};
}

}  // namespace

void addPrimitiveCommand(CommandRegistry& registry) {
  registry.add<PrimitiveArguments>(
      {"primitive",
       "Write the narrow-band level set of an analytic shape, with the exact signed distance at "
       "every band voxel (references for accuracy tests). Axes of the torus and the cylinder are "
       "parallel to +z.\n"
       "  sphere   --center C --radius R\n"
       "  box      --min A --max B\n"
       "  torus    --center C --major R --minor r   (0 < r < R)\n"
       "  cylinder --center C --radius R --height H (capped; C is the axis midpoint)\n"
       "Example: d2vdb primitive torus --major 1 --minor 0.35 --voxel-size 0.02 torus.vdb",
       "use a coarser --voxel-size or --resolution, a smaller --half-width, or a lower "
       "--max-voxels to be refused early",
       declarePrimitive, runPrimitive, outputsOfPrimitive});
}

}  // namespace d2vdb::cli
