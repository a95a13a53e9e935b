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
#include "d2vdb/core/Version.h"
#include "d2vdb/field/detail/OpenVdbSetup.h"
#include "d2vdb/io/GridSelection.h"

namespace d2vdb {

using detail::ensureOpenVdbInitialized;
namespace {

// The first 8 bytes of every .vdb file: OPENVDB_MAGIC as a little-endian int64.
constexpr std::int64_t kVdbMagic = openvdb::OPENVDB_MAGIC;
// Oldest file format whose layout checkFileStructure() walks (OpenVDB 3.0, 2014).
constexpr std::uint32_t kOldestWalkedFormat = openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION;
constexpr std::size_t kUuidLength = 36;

std::string quoted(const std::filesystem::path& path) {
  return "'" + path.string() + "'";
}

// Sequential little-endian reads from a file of known size; every read is bounds-checked so that
// a truncated or corrupt header is reported with its byte offset instead of being trusted.
class CheckedReader {
 public:
  CheckedReader(const std::filesystem::path& path, std::uint64_t size)
      : path_(path), size_(size), in_(path, std::ios::binary) {
    if (!in_) throw InputError("cannot open " + quoted(path) + " for reading (permissions?)");
  }

  std::uint64_t offset() const { return offset_; }
  std::uint64_t size() const { return size_; }

  template <typename T>
  T read(const char* what) {
    T value{};
    readBytes(reinterpret_cast<char*>(&value), sizeof(T), what);
    return value;
  }

  std::string readString(const char* what) {
    const auto length = read<std::uint32_t>(what);
    requireAvailable(length, what);
    std::string text(length, '\0');
    readBytes(text.data(), length, what);
    return text;
  }

  void skip(std::uint64_t count, const char* what) {
    requireAvailable(count, what);
    seek(offset_ + count, what);
  }

  void seek(std::uint64_t position, const char* what) {
    if (position > size_) fail(std::string(what) + " lies beyond the end of the file");
    in_.seekg(static_cast<std::streamoff>(position));
    if (!in_) fail(std::string("cannot seek to ") + what);
    offset_ = position;
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(quoted(path_) + " is truncated or corrupt: " + problem + " (at byte " +
                     std::to_string(offset_) + " of " + std::to_string(size_) + ")");
  }

 private:
  void requireAvailable(std::uint64_t count, const char* what) const {
    if (count > size_ - offset_) {
      fail(std::string(what) + " needs " + std::to_string(count) + " bytes but only " +
           std::to_string(size_ - offset_) + " remain");
    }
  }

  void readBytes(char* destination, std::uint64_t count, const char* what) {
    requireAvailable(count, what);
    in_.read(destination, static_cast<std::streamsize>(count));
    if (!in_) fail(std::string("read error in ") + what);
    offset_ += count;
  }

  std::filesystem::path path_;
  std::uint64_t size_;
  std::uint64_t offset_ = 0;
  std::ifstream in_;
};

// Checks that `path` names a non-empty regular file starting with the VDB magic number; returns
// its size.
std::uint64_t checkIsVdbFile(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) {
    throw InputError("the file " + quoted(path) + " does not exist");
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw InputError(quoted(path) + " is not a regular file (a .vdb file was expected)");
  }
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError("cannot determine the size of " + quoted(path) + ": " + ec.message());
  if (size == 0)
    throw InputError("the file " + quoted(path) + " is empty (a .vdb file was expected)");
  std::int64_t magic = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open " + quoted(path) + " for reading (permissions?)");
  if (size < sizeof(magic) || !in.read(reinterpret_cast<char*>(&magic), sizeof(magic)) ||
      magic != kVdbMagic) {
    throw InputError(quoted(path) +
                     " is not a .vdb file (it does not start with the VDB magic "
                     "number)");
  }
  return size;
}

// Walks the file header, the file metadata and the chain of grid descriptors, checking every
// length and offset against the file size, so that OpenVDB never reads past the end of a
// truncated file (it would act on garbage sizes). Grid contents are left to OpenVDB.
void checkFileStructure(const std::filesystem::path& path, std::uint64_t size) {
  CheckedReader reader(path, size);
  reader.skip(sizeof(std::int64_t), "the magic number");
  const auto formatVersion = reader.read<std::uint32_t>("the file format version");
  if (formatVersion > openvdb::OPENVDB_FILE_VERSION) {
    throw InputError(quoted(path) + " uses .vdb file format " + std::to_string(formatVersion) +
                     ", newer than the " + std::to_string(openvdb::OPENVDB_FILE_VERSION) +
                     " this OpenVDB reads; re-save it with OpenVDB " +
                     std::to_string(openvdb::OPENVDB_LIBRARY_MAJOR_VERSION) + " or older");
  }
  if (formatVersion < kOldestWalkedFormat) return;  // older layouts are left to OpenVDB

  reader.skip(2 * sizeof(std::uint32_t), "the library version");
  const auto hasGridOffsets = reader.read<std::uint8_t>("the grid-offsets flag");
  reader.skip(kUuidLength, "the file UUID");

  const auto metadataCount = reader.read<std::uint32_t>("the file metadata count");
  for (std::uint32_t i = 0; i < metadataCount; ++i) {
    reader.readString("a file metadata name");
    reader.readString("a file metadata type");
    reader.skip(reader.read<std::uint32_t>("a file metadata size"), "a file metadata value");
  }

  const auto gridCount = reader.read<std::int32_t>("the grid count");
  if (gridCount < 0) reader.fail("negative grid count " + std::to_string(gridCount));
  if (hasGridOffsets == 0) return;  // a stream-format file: no offsets to check

  for (std::int32_t grid = 0; grid < gridCount; ++grid) {
    const std::string name = reader.readString("a grid name");
    reader.readString("a grid type");
    reader.readString("a grid instance parent");
    const auto gridStart = reader.read<std::int64_t>("a grid start offset");
    const auto blockStart = reader.read<std::int64_t>("a grid data offset");
    const auto gridEnd = reader.read<std::int64_t>("a grid end offset");
    const auto descriptorEnd = static_cast<std::int64_t>(reader.offset());
    const auto fileSize = static_cast<std::int64_t>(size);
    if (gridStart != descriptorEnd || gridEnd < gridStart ||
        (blockStart != 0 && (blockStart < gridStart || blockStart > gridEnd))) {
      reader.fail("grid '" + name + "' has inconsistent offsets");
    }
    if (gridEnd > fileSize) {
      reader.fail("grid '" + name + "' (" + std::to_string(grid + 1) + " of " +
                  std::to_string(gridCount) + ") ends at byte " + std::to_string(gridEnd) +
                  ", beyond the end of the file");
    }
    reader.seek(static_cast<std::uint64_t>(gridEnd), "the next grid");
  }
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
void rejectNonFiniteValues(const GridT& grid, const std::filesystem::path& path) {
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
    throw InputError("grid '" + grid.getName() + "' in " + quoted(path) + " holds " +
                     std::to_string(count) + " non-finite value" + (count > 1 ? "s" : "") +
                     ", e.g. " + example + "; the file is corrupt or was written from bad data");
  }
}

void rejectNonFiniteValues(const openvdb::GridBase& grid, const std::filesystem::path& path) {
  if (const auto* floatGrid = dynamic_cast<const openvdb::FloatGrid*>(&grid)) {
    rejectNonFiniteValues(*floatGrid, path);
  } else if (const auto* doubleGrid = dynamic_cast<const openvdb::DoubleGrid*>(&grid)) {
    rejectNonFiniteValues(*doubleGrid, path);
  } else if (const auto* vec3sGrid = dynamic_cast<const openvdb::Vec3SGrid*>(&grid)) {
    rejectNonFiniteValues(*vec3sGrid, path);
  } else if (const auto* vec3dGrid = dynamic_cast<const openvdb::Vec3DGrid*>(&grid)) {
    rejectNonFiniteValues(*vec3dGrid, path);
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
    const double halfWidth = halfWidthFor(*copy, options);
    if (halfWidth > 0.0) copy->insertMeta(kHalfWidthMetadata, openvdb::DoubleMetadata(halfWidth));
    copy->setSaveFloatAsHalf(options.halfFloat);
    prepared.push_back(copy);
  }
  return prepared;
}

}  // namespace

std::vector<openvdb::GridBase::Ptr> readAllGrids(const std::filesystem::path& path) {
  ensureOpenVdbInitialized();
  const std::uint64_t size = checkIsVdbFile(path);
  checkFileStructure(path, size);

  openvdb::GridPtrVecPtr grids;
  try {
    // The whole file is read through a stream that throws on any short read: no delayed
    // loading, no memory mapping, no garbage values after an unexpected end of file.
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot open " + quoted(path) + " for reading (permissions?)");
    in.exceptions(std::ios::failbit | std::ios::badbit | std::ios::eofbit);
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    grids = stream.getGrids();
  } catch (const InputError&) {
    throw;
  } catch (const std::ios_base::failure&) {
    throw InputError("cannot read " + quoted(path) +
                     ": unexpected end of file or read error (the file is truncated or corrupt)");
  } catch (const std::exception& error) {
    throw InputError("cannot read " + quoted(path) + ": " + error.what() +
                     " (the file is corrupt or not a grid file this OpenVDB understands)");
  }
  if (!grids || grids->empty()) throw InputError(quoted(path) + " contains no grids");
  std::vector<openvdb::GridBase::Ptr> result(grids->begin(), grids->end());
  for (const openvdb::GridBase::Ptr& grid : result) rejectNonFiniteValues(*grid, path);
  return result;
}

openvdb::FloatGrid::Ptr readLevelSet(const std::filesystem::path& path,
                                     const std::string& gridName) {
  return openvdb::gridPtrCast<openvdb::FloatGrid>(
      selectGrid(readAllGrids(path), quoted(path), gridName, ScalarGridTypes::Float));
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
      throw RuntimeFailure("cannot write " + quoted(path) + ": " + error.what());
    }
    std::error_code ec;
    if (std::filesystem::file_size(temporary, ec) == 0 || ec) {
      throw RuntimeFailure("cannot write " + quoted(path) + ": nothing was written (disk full?)");
    }
  });
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
