// Reading and writing .vdb files: validation, grid preparation (names, metadata, half floats)
// and atomic writes.
#include "d2vdb/io/VdbFile.h"

#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/core/Version.h"
#include "d2vdb/field/MeshToLevelSet.h"
#include "d2vdb/field/detail/OpenVdbSetup.h"
#include "d2vdb/io/GridSelection.h"
#include "d2vdb/io/VdbPartialReader.h"
#include "d2vdb/io/detail/VdbFormatCheck.h"
#include "d2vdb/io/detail/VdbStream.h"

namespace d2vdb {

using detail::checkVdbStream;
using detail::ensureOpenVdbInitialized;
namespace {

// The first 8 bytes of every .vdb file: OPENVDB_MAGIC as a little-endian int64.
constexpr std::int64_t kVdbMagic = openvdb::OPENVDB_MAGIC;

// Checks that `path` names a non-empty regular file starting with the VDB magic number; returns
// its size.
std::uint64_t checkIsVdbFile(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) {
    throw InputError("the file " + quotedPath(path) + " does not exist");
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw InputError(quotedPath(path) + " is not a regular file (a .vdb file was expected)");
  }
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  if (ec)
    throw InputError("cannot determine the size of " + quotedPath(path) + ": " + ec.message());
  if (size == 0)
    throw InputError("the file " + quotedPath(path) + " is empty (a .vdb file was expected)");
  std::int64_t magic = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open " + quotedPath(path) + " for reading (permissions?)");
  if (size < sizeof(magic) || !in.read(reinterpret_cast<char*>(&magic), sizeof(magic)) ||
      magic != kVdbMagic) {
    throw InputError(quotedPath(path) +
                     " is not a .vdb file (it does not start with the VDB magic "
                     "number)");
  }
  return size;
}

bool isFiniteValue(float value) {
  return std::isfinite(value);
}
bool isFiniteValue(double value) {
  return std::isfinite(value);
}
bool isFiniteValue(const openvdb::Vec3s& value) {
  return value.isFinite();
}
bool isFiniteValue(const openvdb::Vec3d& value) {
  return value.isFinite();
}

// Throws InputError when any value of the grid (background, tiles, voxels, active or not) is NaN
// or infinite, with the count and one location.
template <typename GridT>
void rejectNonFiniteValues(const GridT& grid, const std::string& name) {
  using TreeT = typename GridT::TreeType;
  std::uint64_t count = 0;
  std::string example;
  const auto record = [&](const auto& value, const openvdb::Coord& ijk, const char* where) {
    if (count++ > 0) return;
    std::ostringstream text;
    const openvdb::Vec3d world = grid.indexToWorld(ijk);
    text << value << " at " << where << " (" << ijk.x() << ", " << ijk.y() << ", " << ijk.z()
         << "), world (" << world.x() << ", " << world.y() << ", " << world.z() << ")";
    example = text.str();
  };
  if (!isFiniteValue(grid.background())) {
    ++count;
    std::ostringstream text;
    text << grid.background() << " as the background value";
    example = text.str();
  }
  for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
    const auto* values = leaf->buffer().data();
    for (openvdb::Index offset = 0; offset < TreeT::LeafNodeType::SIZE; ++offset) {
      if (!isFiniteValue(values[offset])) {
        record(values[offset], leaf->offsetToGlobalCoord(offset),
               leaf->isValueOn(offset) ? "active voxel" : "inactive voxel");
      }
    }
  }
  auto tile = grid.tree().cbeginValueAll();
  tile.setMaxDepth(TreeT::ValueAllCIter::LEAF_DEPTH - 1);  // tiles only; leaves were done above
  for (; tile; ++tile) {
    if (!isFiniteValue(*tile)) record(*tile, tile.getCoord(), "the tile starting at index");
  }
  if (count > 0) {
    throw InputError("grid '" + grid.getName() + "' in '" + name + "' holds " +
                     std::to_string(count) + " non-finite value" + (count > 1 ? "s" : "") +
                     ", e.g. " + example + "; the file is corrupt or was written from bad data");
  }
}

// Throws InputError when the grid's transform cannot map between index and world space: a voxel
// size that is not finite and positive, or a map whose stored inverse does not undo it.
void rejectUnusableTransform(const openvdb::GridBase& grid, const std::string& name) {
  const openvdb::math::Transform& transform = grid.transform();
  const openvdb::Vec3d voxelSize = transform.voxelSize();
  bool usable = voxelSize.isFinite() && voxelSize.x() > 0 && voxelSize.y() > 0 && voxelSize.z() > 0;
  if (usable && transform.isLinear()) {
    // The scale maps store their inverse separately; it must undo the map.
    for (const openvdb::Vec3d& index :
         {openvdb::Vec3d(0, 0, 0), openvdb::Vec3d(1, 2, 3), openvdb::Vec3d(-100, 50, 7)}) {
      const openvdb::Vec3d back = transform.worldToIndex(transform.indexToWorld(index));
      usable = usable && back.isFinite() && (back - index).length() <= 1e-6 * (1 + index.length());
    }
  }
  if (!usable) {
    std::ostringstream text;
    text << "grid '" << grid.getName() << "' in '" << name << "' has an unusable transform ("
         << transform.mapType() << ", voxel size " << voxelSize
         << "): its voxels must have a finite positive size and the map an exact inverse";
    throw InputError(text.str());
  }
}

void rejectNonFiniteValues(const openvdb::GridBase& grid, const std::string& name) {
  if (const auto* floatGrid = dynamic_cast<const openvdb::FloatGrid*>(&grid)) {
    rejectNonFiniteValues(*floatGrid, name);
  } else if (const auto* doubleGrid = dynamic_cast<const openvdb::DoubleGrid*>(&grid)) {
    rejectNonFiniteValues(*doubleGrid, name);
  } else if (const auto* vec3sGrid = dynamic_cast<const openvdb::Vec3SGrid*>(&grid)) {
    rejectNonFiniteValues(*vec3sGrid, name);
  } else if (const auto* vec3dGrid = dynamic_cast<const openvdb::Vec3DGrid*>(&grid)) {
    rejectNonFiniteValues(*vec3dGrid, name);
  }
}

bool isStandardGridType(const openvdb::GridBase& grid) {
  const std::string& type = grid.type();
  return type == openvdb::BoolGrid::gridType() || type == openvdb::MaskGrid::gridType() ||
         type == openvdb::FloatGrid::gridType() || type == openvdb::DoubleGrid::gridType() ||
         type == openvdb::Int32Grid::gridType() || type == openvdb::Int64Grid::gridType() ||
         type == openvdb::Vec3SGrid::gridType() || type == openvdb::Vec3DGrid::gridType() ||
         type == openvdb::Vec3IGrid::gridType();
}

// The half-width to record for `grid`: the option if given, else background / voxel size for
// float and double level sets (rounded to float precision, the precision of a float background,
// so that 0.15f / 0.05 records 3), else 0 (nothing recorded).
double halfWidthFor(const openvdb::GridBase& grid, const VdbWriteOptions& options) {
  if (options.halfWidth > 0.0) return options.halfWidth;
  if (grid.getGridClass() != openvdb::GRID_LEVEL_SET) return 0.0;
  const double voxelSize = grid.voxelSize()[0];
  if (!(voxelSize > 0.0)) return 0.0;
  if (const auto* floatGrid = dynamic_cast<const openvdb::FloatGrid*>(&grid)) {
    return static_cast<double>(static_cast<float>(double(floatGrid->background()) / voxelSize));
  }
  if (const auto* doubleGrid = dynamic_cast<const openvdb::DoubleGrid*>(&grid)) {
    return doubleGrid->background() / voxelSize;
  }
  return 0.0;
}

// Shallow copies (shared trees) named and annotated for writing.
openvdb::GridPtrVec prepareGridsForWriting(const openvdb::GridPtrVec& grids,
                                           const VdbWriteOptions& options) {
  if (grids.empty()) throw InputError("writing a .vdb file: no grids were given");
  std::set<std::string> usedNames;
  for (std::size_t i = 0; i < grids.size(); ++i) {
    if (!grids[i]) throw InputError("writing a .vdb file: grid " + std::to_string(i) + " is null");
    if (!isStandardGridType(*grids[i])) {
      throw InputError("writing a .vdb file: grid '" + grids[i]->getName() + "' has type " +
                       grids[i]->type() +
                       ", which is not a standard OpenVDB grid type that "
                       "other tools can read; convert it to a float, double, int, bool, mask or "
                       "vec3 grid");
    }
    const std::string& name = grids[i]->getName();
    if (!name.empty() && !usedNames.insert(name).second) {
      throw InputError("writing a .vdb file: two grids are named '" + name +
                       "'; give each grid a distinct name");
    }
  }

  const std::string creator = std::string("d2vdb ") + kVersion;
  openvdb::GridPtrVec prepared;
  prepared.reserve(grids.size());
  for (std::size_t i = 0; i < grids.size(); ++i) {
    openvdb::GridBase::Ptr copy = grids[i]->copyGrid();  // shares the tree, copies metadata
    if (copy->getName().empty()) {
      const bool isLevelSet = copy->getGridClass() == openvdb::GRID_LEVEL_SET;
      const std::string base = isLevelSet ? "surface" : "grid_" + std::to_string(i);
      std::string name = base;
      for (int n = 2; usedNames.count(name) > 0; ++n) name = base + "_" + std::to_string(n);
      usedNames.insert(name);
      copy->setName(name);
    }
    copy->setCreator(creator);
    if (!options.source.empty()) {
      copy->insertMeta(kSourceMetadata, openvdb::StringMetadata(options.source));
    }
    if (copy->getGridClass() == openvdb::GRID_LEVEL_SET &&
        !copy->getMetadata<openvdb::StringMetadata>(kDistanceKindMetadata)) {
      copy->insertMeta(kDistanceKindMetadata, openvdb::StringMetadata("signed"));
    }
    const double halfWidth = halfWidthFor(*copy, options);
    if (halfWidth > 0.0) copy->insertMeta(kHalfWidthMetadata, openvdb::DoubleMetadata(halfWidth));
    copy->setSaveFloatAsHalf(options.halfFloat);
    prepared.push_back(copy);
  }
  return prepared;
}

}  // namespace

std::vector<openvdb::GridBase::Ptr> detail::readVdbStream(std::istream& in, std::uint64_t size,
                                                          const std::string& name) {
  const std::streampos start = in.tellg();
  // OpenVDB trusts every size in the stream; the walk makes sure each of them is consistent.
  checkVdbStream(in, size, name);
  in.clear();
  in.seekg(start);

  openvdb::GridPtrVecPtr grids;
  const std::ios::iostate exceptions = in.exceptions();
  try {
    // Read through a stream that throws on any short read: no delayed loading, no memory
    // mapping, no garbage values after an unexpected end of file.
    in.exceptions(std::ios::failbit | std::ios::badbit | std::ios::eofbit);
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    grids = stream.getGrids();
    in.exceptions(exceptions);
  } catch (const std::ios_base::failure&) {
    in.exceptions(exceptions);
    throw InputError("cannot read '" + name +
                     "': unexpected end of file or read error (the file is truncated or corrupt)");
  } catch (const std::exception& error) {
    in.exceptions(exceptions);
    throw InputError("cannot read '" + name + "': " + error.what() +
                     " (the file is corrupt or not a grid file this OpenVDB understands)");
  }
  if (!grids || grids->empty()) throw InputError("'" + name + "' contains no grids");
  std::vector<openvdb::GridBase::Ptr> result(grids->begin(), grids->end());
  for (const openvdb::GridBase::Ptr& grid : result) {
    rejectUnusableTransform(*grid, name);
    rejectNonFiniteValues(*grid, name);
  }
  return result;
}

std::vector<openvdb::GridBase::Ptr> readAllGrids(const std::filesystem::path& path) {
  ensureOpenVdbInitialized();
  const std::uint64_t size = checkIsVdbFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open " + quotedPath(path) + " for reading (permissions?)");
  return detail::readVdbStream(in, size, path.string());
}

openvdb::FloatGrid::Ptr readLevelSet(const std::filesystem::path& path,
                                     const std::string& gridName) {
  return openvdb::gridPtrCast<openvdb::FloatGrid>(
      selectGrid(readAllGrids(path), quotedPath(path), gridName, ScalarGridTypes::Float));
}

void writeVdb(const std::filesystem::path& path, const openvdb::GridPtrVec& grids,
              const VdbWriteOptions& options) {
  ensureOpenVdbInitialized();
  const openvdb::GridPtrVec prepared = prepareGridsForWriting(grids, options);

  std::uint32_t compression = openvdb::io::COMPRESS_ACTIVE_MASK;
  if (options.blosc) {
    compression |= openvdb::io::Archive::hasBloscCompression() ? openvdb::io::COMPRESS_BLOSC
                                                               : openvdb::io::COMPRESS_ZIP;
  }
  openvdb::MetaMap fileMetadata;
  fileMetadata.insertMeta("creator", openvdb::StringMetadata(std::string("d2vdb ") + kVersion));

  writeFileAtomically(path, [&](const std::filesystem::path& temporary) {
    try {
      openvdb::io::File file(temporary.string());
      file.setCompression(compression);
      file.write(prepared, fileMetadata);
      file.close();
    } catch (const std::exception& error) {
      throw RuntimeFailure("cannot write " + quotedPath(path) + ": " + error.what());
    }
    std::error_code ec;
    if (std::filesystem::file_size(temporary, ec) == 0 || ec) {
      throw RuntimeFailure("cannot write " + quotedPath(path) +
                           ": nothing was written (disk full?)");
    }
  });
}

VdbPartialReader::VdbPartialReader(const std::filesystem::path& path) : path_(path) {
  ensureOpenVdbInitialized();
  const std::uint64_t size = checkIsVdbFile(path);
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot open " + quotedPath(path) + " for reading (permissions?)");
    checkVdbStream(in, size, path.string());
  }
  try {
    openvdb::io::File file(path.string());
    file.open(/*delayLoad=*/false);
    const openvdb::GridPtrVecPtr grids = file.readAllGridMetadata();
    if (grids) metadata_.assign(grids->begin(), grids->end());
    file.close();
  } catch (const std::exception& error) {
    throw InputError("cannot read '" + path.string() + "': " + error.what() +
                     " (the file is corrupt or not a grid file this OpenVDB understands)");
  }
  if (metadata_.empty()) throw InputError(quotedPath(path) + " contains no grids");
  for (const openvdb::GridBase::Ptr& grid : metadata_)
    rejectUnusableTransform(*grid, path.string());
}

std::vector<openvdb::GridBase::Ptr> VdbPartialReader::read(const openvdb::BBoxd& worldBox) const {
  return readGrids(&worldBox);
}

std::vector<openvdb::GridBase::Ptr> VdbPartialReader::readAll() const {
  return readGrids(nullptr);
}

std::vector<openvdb::GridBase::Ptr> VdbPartialReader::readGrids(
    const openvdb::BBoxd* worldBox) const {
  std::vector<openvdb::GridBase::Ptr> grids;
  try {
    // Memory-mapped (OpenVDB's delayed loading, the file having been checked whole): skipping the
    // leaves outside the box is then a pointer move, not a system call per leaf.
    openvdb::io::File file(path_.string());
    file.open(/*delayLoad=*/true);
    for (const openvdb::GridBase::Ptr& grid : metadata_) {
      grids.push_back(worldBox ? file.readGrid(grid->getName(), *worldBox)
                               : file.readGrid(grid->getName()));
    }
    file.close();
  } catch (const std::exception& error) {
    throw InputError("cannot read '" + path_.string() + "': " + error.what() +
                     " (the file is corrupt or not a grid file this OpenVDB understands)");
  }
  for (const openvdb::GridBase::Ptr& grid : grids) {
    rejectUnusableTransform(*grid, path_.string());
    rejectNonFiniteValues(*grid, path_.string());
  }
  return grids;
}

std::vector<VdbGridInfo> describeVdbFile(const std::filesystem::path& path) {
  return summarizeGrids(readAllGrids(path));
}

std::vector<VdbGridInfo> summarizeGrids(const std::vector<openvdb::GridBase::Ptr>& grids) {
  std::vector<VdbGridInfo> infos;
  infos.reserve(grids.size());
  for (const openvdb::GridBase::Ptr& grid : grids) {
    if (!grid) continue;
    VdbGridInfo info;
    info.name = grid->getName();
    info.valueType = grid->valueType();
    info.gridClass = openvdb::GridBase::gridClassToString(grid->getGridClass());
    info.voxelSize = grid->voxelSize();
    info.activeVoxelCount = grid->activeVoxelCount();
    info.indexBoundingBox = grid->evalActiveVoxelBoundingBox();
    if (!info.indexBoundingBox.empty()) {
      info.worldBoundingBox = grid->transform().indexToWorld(info.indexBoundingBox);
    }
    info.memoryBytes = grid->memUsage();
    for (auto meta = grid->beginMeta(); meta != grid->endMeta(); ++meta) {
      info.metadata.emplace_back(meta->first, meta->second ? meta->second->str() : std::string());
    }
    infos.push_back(std::move(info));
  }
  return infos;
}

}  // namespace d2vdb
