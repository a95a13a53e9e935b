// The bounds-checked walk over a .vdb stream (header, metadata, grid descriptors, trees) done
// before OpenVDB parses it.
#include "d2vdb/io/detail/VdbFormatCheck.h"

#include <blosc.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/openvdb.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <bitset>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/field/detail/OpenVdbSetup.h"

namespace d2vdb::detail {
namespace {

// File format versions whose layout the walk knows: 222 (node mask compression, OpenVDB 3.0),
// 223 (Blosc, point index grids) and 224 (multi-pass I/O, which only point data grids use).
constexpr std::uint32_t kOldestFormat = openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION;
constexpr std::uint32_t kNewestFormat = openvdb::OPENVDB_FILE_VERSION;
static_assert(kNewestFormat == 224, "a new .vdb file format: teach checkVdbStream its layout");

// Node origins beyond this many voxels from the origin are refused: no tool writes them, and
// OpenVDB's bounding-box arithmetic near the int32 limits overflows.
constexpr std::int64_t kCoordinateLimit = std::int64_t(1) << 30;

// The largest metadata item count, node count etc. for which a loop is even started is bounded by
// the bytes left, since every item takes at least one byte; nothing else needs a limit.

constexpr std::size_t kUuidBytes = 36;  // 32 hex digits and 4 hyphens, no terminator
constexpr std::uint32_t kNoCompressedSizes = std::numeric_limits<std::uint32_t>::max();
// points/StreamCompression.h: buffers below this many bytes are padded to it before compression.
constexpr std::size_t kBloscPadBytes = 128;

enum class LeafKind { Values, Bool, Mask };

// How a tree type is laid out on disk: OpenVDB's standard 5-4-3 trees of one value type.
struct TreeLayout {
  std::string typeName;    // e.g. "Tree_float_5_4_3"
  std::string valueName;   // e.g. "float"
  std::size_t valueBytes;  // sizeof(ValueType): root values, tiles and uncompressed node values
  std::size_t halfBytes;   // bytes of the half-float form when saved as half; 0 if not real
  bool boolValues;         // values are C++ bools: every stored byte must be 0 or 1
  LeafKind leaf;
  std::size_t leafBytes;       // sizeof(LeafNode) in memory
  std::size_t lowerNodeBytes;  // sizeof(InternalNode<Leaf, 4>)
  std::size_t upperNodeBytes;  // sizeof(InternalNode<..., 5>)
};

template <typename GridT>
TreeLayout layoutOf(LeafKind leaf) {
  using TreeT = typename GridT::TreeType;
  using RootT = typename TreeT::RootNodeType;
  using UpperT = typename RootT::ChildNodeType;
  using LowerT = typename UpperT::ChildNodeType;
  using LeafT = typename LowerT::ChildNodeType;
  using ValueT = typename TreeT::ValueType;
  static_assert(UpperT::LOG2DIM == 5 && LowerT::LOG2DIM == 4 && LeafT::LOG2DIM == 3,
                "the walk assumes OpenVDB's standard 5-4-3 tree configuration");
  using Half = openvdb::io::RealToHalf<ValueT>;
  return TreeLayout{TreeT::treeType(),
                    openvdb::typeNameAsString<ValueT>(),
                    sizeof(ValueT),
                    Half::isReal ? sizeof(typename Half::HalfT) : 0,
                    std::is_same_v<ValueT, bool>,
                    leaf,
                    sizeof(LeafT),
                    sizeof(LowerT),
                    sizeof(UpperT)};
}

const std::vector<TreeLayout>& treeLayouts() {
  static const std::vector<TreeLayout> layouts = {
      layoutOf<openvdb::FloatGrid>(LeafKind::Values),
      layoutOf<openvdb::DoubleGrid>(LeafKind::Values),
      layoutOf<openvdb::Int32Grid>(LeafKind::Values),
      layoutOf<openvdb::Int64Grid>(LeafKind::Values),
      layoutOf<openvdb::Vec3SGrid>(LeafKind::Values),
      layoutOf<openvdb::Vec3DGrid>(LeafKind::Values),
      layoutOf<openvdb::Vec3IGrid>(LeafKind::Values),
      layoutOf<openvdb::BoolGrid>(LeafKind::Bool),
      layoutOf<openvdb::MaskGrid>(LeafKind::Mask),
  };
  return layouts;
}

// Registered metadata types whose value is a fixed number of bytes (TypedMetadata<T> reads
// sizeof(T) bytes whatever size the file states). Point index metadata are int32/int64 values.
std::optional<std::size_t> fixedMetadataBytes(const std::string& type) {
  static const std::pair<const char*, std::size_t> sizes[] = {
      {"bool", 1},    {"double", 8},  {"float", 4},   {"int32", 4},       {"int64", 8},
      {"vec2i", 8},   {"vec2s", 8},   {"vec2d", 16},  {"vec3i", 12},      {"vec3s", 12},
      {"vec3d", 24},  {"vec4i", 16},  {"vec4s", 16},  {"vec4d", 32},      {"mat4s", 64},
      {"mat4d", 128}, {"ptidx32", 4}, {"ptidx64", 8}, {"ptdataidx32", 4}, {"ptdataidx64", 8},
  };
  for (const auto& [name, bytes] : sizes) {
    if (type == name) return bytes;
  }
  return std::nullopt;
}

// Bytes each linear map reads (math/Maps.h): Vec3d = 24 bytes, Mat4d = 128 bytes.
std::optional<std::size_t> linearMapBytes(const std::string& type) {
  if (type == "AffineMap" || type == "UnitaryMap") return 128;
  if (type == "ScaleMap" || type == "UniformScaleMap") return 5 * 24;
  if (type == "TranslationMap") return 24;
  if (type == "ScaleTranslateMap" || type == "UniformScaleTranslateMap") return 6 * 24;
  return std::nullopt;
}

// A node's value/child mask: 2^(3 log2Dim) bits.
class NodeMask {
 public:
  explicit NodeMask(int log2Dim) : words_(std::size_t(1) << (3 * log2Dim - 6), 0) {}
  std::size_t bytes() const { return words_.size() * sizeof(std::uint64_t); }
  char* data() { return reinterpret_cast<char*>(words_.data()); }
  std::uint64_t countOn() const {
    std::uint64_t count = 0;
    for (const std::uint64_t word : words_) count += std::bitset<64>(word).count();
    return count;
  }
  bool isOn(std::size_t bit) const { return (words_[bit >> 6] >> (bit & 63)) & 1u; }
  bool intersects(const NodeMask& other) const {
    for (std::size_t i = 0; i < words_.size(); ++i) {
      if (words_[i] & other.words_[i]) return true;
    }
    return false;
  }
  std::size_t size() const { return words_.size() * 64; }

 private:
  std::vector<std::uint64_t> words_;
};

struct Coord {
  std::int32_t x = 0, y = 0, z = 0;
  bool operator<(const Coord& other) const {  // openvdb::Coord's order: x, then y, then z
    if (x != other.x) return x < other.x;
    if (y != other.y) return y < other.y;
    return z < other.z;
  }
  bool operator==(const Coord& other) const { return x == other.x && y == other.y && z == other.z; }
  std::string text() const {
    return "(" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) + ")";
  }
};

class Walker {
 public:
  Walker(std::istream& in, std::uint64_t size, std::string name)
      : in_(in), size_(size), name_(std::move(name)) {}

  std::uint64_t offset() const { return offset_; }
  std::uint64_t remaining() const { return size_ - offset_; }

  void setContext(std::string context) { context_ = std::move(context); }

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(
        "'" + name_ + "' is truncated or corrupt: " + (context_.empty() ? "" : context_ + ": ") +
        problem + " (at byte " + std::to_string(offset_) + " of " + std::to_string(size_) + ")");
  }

  [[noreturn]] void unsupported(const std::string& problem) const {
    throw InputError("'" + name_ + "': " + (context_.empty() ? "" : context_ + ": ") + problem);
  }

  void require(std::uint64_t count, const std::string& what) const {
    if (count > remaining()) {
      fail(what + " needs " + std::to_string(count) + " bytes but only " +
           std::to_string(remaining()) + " remain");
    }
  }

  void read(char* destination, std::uint64_t count, const std::string& what) {
    require(count, what);
    if (count == 0) return;
    in_.read(destination, static_cast<std::streamsize>(count));
    if (!in_ || static_cast<std::uint64_t>(in_.gcount()) != count) fail("read error in " + what);
    offset_ += count;
  }

  template <typename T>
  T value(const std::string& what) {
    T result{};
    read(reinterpret_cast<char*>(&result), sizeof(T), what);
    return result;
  }

  std::vector<char> bytes(std::uint64_t count, const std::string& what) {
    require(count, what);
    std::vector<char> result(count);
    read(result.data(), count, what);
    return result;
  }

  // openvdb::readString: a uint32 length, then that many bytes.
  std::string string(const std::string& what) {
    const auto length = value<std::uint32_t>("the length of " + what);
    require(length, what);
    std::string text(length, '\0');
    read(text.data(), length, what);
    return text;
  }

  void skip(std::uint64_t count, const std::string& what) {
    require(count, what);
    if (count == 0) return;
    in_.seekg(static_cast<std::streamoff>(count), std::ios::cur);
    if (!in_) fail("cannot seek over " + what);
    offset_ += count;
  }

  void readMask(NodeMask& mask, const std::string& what) { read(mask.data(), mask.bytes(), what); }

  // The bytes from `start` to the current offset, read again (the walk continues from here).
  std::string bytesSince(std::uint64_t start) {
    std::string bytes(offset_ - start, '\0');
    in_.seekg(static_cast<std::streamoff>(start));
    in_.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    in_.seekg(static_cast<std::streamoff>(offset_));
    if (!in_) fail("cannot read the stream again");
    return bytes;
  }

  // A C++ bool as OpenVDB reads it: one byte that must be 0 or 1.
  void checkBoolBytes(const char* data, std::size_t count, const std::string& what) const {
    for (std::size_t i = 0; i < count; ++i) {
      if (data[i] != 0 && data[i] != 1) {
        fail(what + " holds the byte " + std::to_string(int(static_cast<unsigned char>(data[i]))) +
             " where a bool (0 or 1) is stored");
      }
    }
  }

 private:
  std::istream& in_;
  std::uint64_t size_;
  std::string name_;
  std::uint64_t offset_ = 0;
  std::string context_;
};

// The bytes a Blosc buffer decompresses to, provided blosc_cbuffer_validate accepts it, its header
// states exactly its own size and `expected` uncompressed bytes, and decompression yields them.
std::optional<std::vector<char>> bloscDecompressExactly(const std::vector<char>& chunk,
                                                        std::size_t expected) {
  if (chunk.size() < BLOSC_MIN_HEADER_LENGTH) return std::nullopt;
  std::size_t uncompressed = 0;
  if (blosc_cbuffer_validate(chunk.data(), chunk.size(), &uncompressed) != 0) return std::nullopt;
  std::size_t claimed = 0, compressed = 0, blockSize = 0;
  blosc_cbuffer_sizes(chunk.data(), &claimed, &compressed, &blockSize);
  if (compressed != chunk.size() || claimed != expected) return std::nullopt;
  std::vector<char> output(expected);
  if (expected == 0) return output;
  if (blosc_decompress_ctx(chunk.data(), output.data(), expected, 1) !=
      static_cast<int>(expected)) {
    return std::nullopt;
  }
  return output;
}

// The tree walk of one grid.
class TreeWalker {
 public:
  TreeWalker(Walker& walker, const TreeLayout& layout, std::uint32_t compression, bool fromHalf)
      : walker_(walker), layout_(layout), compression_(compression), fromHalf_(fromHalf) {}

  std::uint64_t internalNodes() const { return upperNodes_ + lowerNodes_; }
  std::uint64_t leafNodes() const { return leaves_; }
  std::uint64_t treeBytes() const {
    return upperNodes_ * layout_.upperNodeBytes + lowerNodes_ * layout_.lowerNodeBytes +
           leaves_ * layout_.leafBytes + rootEntries_ * 64;
  }

  // Tree::readTopology, then Tree::readBuffers (RootNode, InternalNode and LeafNode).
  void walkTopology() {
    const auto bufferCount = walker_.value<std::int32_t>("the tree's buffer count");
    if (bufferCount != 1) {
      walker_.fail("the tree's buffer count is " + std::to_string(bufferCount) + ", not 1");
    }
    readValues(1, "the background value");
    const auto tileCount = walker_.value<std::uint32_t>("the root's tile count");
    const auto childCount = walker_.value<std::uint32_t>("the root's child count");
    std::optional<Coord> previous;
    for (std::uint32_t i = 0; i < tileCount; ++i) {
      const Coord origin = readRootOrigin("a root tile", previous);
      readValues(1, "the value of the root tile at " + origin.text());
      const auto active = walker_.value<char>("the active flag of a root tile");
      walker_.checkBoolBytes(&active, 1, "the active flag of the root tile at " + origin.text());
      tiles_.push_back(origin);
      ++rootEntries_;
    }
    previous.reset();
    for (std::uint32_t i = 0; i < childCount; ++i) {
      const Coord origin = readRootOrigin("a root child", previous);
      if (std::binary_search(tiles_.begin(), tiles_.end(), origin)) {
        walker_.fail("the root holds both a tile and a child at " + origin.text());
      }
      ++rootEntries_;
      walkInternalTopology(5, origin);
    }
  }

  void walkBuffers() {
    // RootNode::readBuffers visits its children in key order, which walkTopology required to be
    // the order of the file; internal nodes visit theirs in mask order, as their topology did.
    for (const Coord& origin : leafOrigins_) walkLeafBuffers(origin);
  }

 private:
  // Reads `count` uncompressed values of the tree's value type (root values, inactive values).
  void readValues(std::size_t count, const std::string& what) {
    const std::vector<char> data = walker_.bytes(count * layout_.valueBytes, what);
    if (layout_.boolValues) walker_.checkBoolBytes(data.data(), data.size(), what);
  }

  Coord readRootOrigin(const char* what, std::optional<Coord>& previous) {
    Coord origin;
    origin.x = walker_.value<std::int32_t>(std::string("the origin of ") + what);
    origin.y = walker_.value<std::int32_t>(std::string("the origin of ") + what);
    origin.z = walker_.value<std::int32_t>(std::string("the origin of ") + what);
    constexpr std::int32_t kDim = 1 << (5 + 4 + 3);
    for (const std::int32_t c : {origin.x, origin.y, origin.z}) {
      if (c % kDim != 0) {
        walker_.fail(std::string(what) + " at " + origin.text() +
                     " is not aligned to the root's grid of " + std::to_string(kDim) + " voxels");
      }
      if (std::int64_t(c) < -kCoordinateLimit || std::int64_t(c) + kDim > kCoordinateLimit) {
        walker_.fail(std::string(what) + " at " + origin.text() + " lies beyond +-2^30 voxels");
      }
    }
    if (previous && !(*previous < origin)) {
      walker_.fail(std::string(what) + " at " + origin.text() + " follows " + previous->text() +
                   ": root entries must be stored once each, in increasing order");
    }
    previous = origin;
    return origin;
  }

  // InternalNode::readTopology for a node of 2^log2Dim children per axis.
  void walkInternalTopology(int log2Dim, const Coord& origin) {
    const std::string node = (log2Dim == 5 ? "the upper internal node at "
                                           : "the lower internal "
                                             "node at ") +
                             origin.text();
    NodeMask childMask(log2Dim), valueMask(log2Dim);
    walker_.readMask(childMask, "the child mask of " + node);
    walker_.readMask(valueMask, "the value mask of " + node);
    if (childMask.intersects(valueMask)) {
      walker_.fail(node + " marks a slot both as a child and as an active value");
    }
    (log2Dim == 5 ? upperNodes_ : lowerNodes_) += 1;
    walkCompressedValues(valueMask.size(), valueMask.countOn(), log2Dim, "the values of " + node);
    const int childLog2Dim = log2Dim == 5 ? 4 : 3;
    const int childTotal = log2Dim == 5 ? 4 + 3 : 3;  // log2 of the child's extent in voxels
    const std::size_t dim = std::size_t(1) << log2Dim;
    for (std::size_t slot = 0; slot < childMask.size(); ++slot) {
      if (!childMask.isOn(slot)) continue;
      // InternalNode::offsetToGlobalCoord: slot = (i * dim + j) * dim + k.
      const Coord child{origin.x + std::int32_t((slot / (dim * dim)) << childTotal),
                        origin.y + std::int32_t(((slot / dim) % dim) << childTotal),
                        origin.z + std::int32_t((slot % dim) << childTotal)};
      if (childLog2Dim == 4) {
        walkInternalTopology(4, child);
      } else {
        walkLeafTopology(child);
      }
    }
  }

  // LeafNode::readTopology: the value mask (the mask grid's leaf: its buffer, also a mask).
  void walkLeafTopology(const Coord& origin) {
    NodeMask mask(3);
    walker_.readMask(mask, "the mask of the leaf at " + origin.text());
    leafOrigins_.push_back(origin);
    ++leaves_;
  }

  // LeafNode::readBuffers for the three leaf kinds.
  void walkLeafBuffers(const Coord& origin) {
    const std::string leaf = "the leaf at " + origin.text();
    NodeMask mask(3);
    walker_.readMask(mask, "the value mask of " + leaf);
    if (layout_.leaf == LeafKind::Values) {
      walkCompressedValues(mask.size(), mask.countOn(), 3, "the values of " + leaf);
      return;
    }
    // Bool and mask leaves store their origin again, then (bool) the mask of their values.
    Coord stored;
    stored.x = walker_.value<std::int32_t>("the origin of " + leaf);
    stored.y = walker_.value<std::int32_t>("the origin of " + leaf);
    stored.z = walker_.value<std::int32_t>("the origin of " + leaf);
    if (!(stored == origin)) {
      walker_.fail(leaf + " stores the origin " + stored.text() + " in its data");
    }
    if (layout_.leaf == LeafKind::Bool) {
      NodeMask values(3);
      walker_.readMask(values, "the values of " + leaf);
    }
  }

  // io::readCompressedValues for a node of `destCount` values, `activeCount` of them active.
  void walkCompressedValues(std::size_t destCount, std::uint64_t activeCount, int log2Dim,
                            const std::string& what) {
    const auto metadata = walker_.value<std::int8_t>("the compression flag of " + what);
    if (metadata < openvdb::io::NO_MASK_OR_INACTIVE_VALS ||
        metadata > openvdb::io::NO_MASK_AND_ALL_VALS) {
      walker_.fail(what + " have the unknown compression flag " + std::to_string(int(metadata)));
    }
    using namespace openvdb::io;
    if (metadata == NO_MASK_AND_ONE_INACTIVE_VAL || metadata == MASK_AND_ONE_INACTIVE_VAL ||
        metadata == MASK_AND_TWO_INACTIVE_VALS) {
      readValues(metadata == MASK_AND_TWO_INACTIVE_VALS ? 2 : 1, "the inactive values of " + what);
    }
    if (metadata == MASK_AND_NO_INACTIVE_VALS || metadata == MASK_AND_ONE_INACTIVE_VAL ||
        metadata == MASK_AND_TWO_INACTIVE_VALS) {
      NodeMask selection(log2Dim);
      walker_.readMask(selection, "the inside/outside mask of " + what);
    }
    std::uint64_t count = destCount;
    if ((compression_ & COMPRESS_ACTIVE_MASK) && metadata != NO_MASK_AND_ALL_VALS) {
      count = activeCount;
    }
    if (fromHalf_ && layout_.halfBytes > 0) {
      // HalfReader: nothing at all is stored for an empty half-float array.
      if (count > 0) walkData(count * layout_.halfBytes, what);
    } else {
      const std::vector<char> values = walkData(count * layout_.valueBytes, what);
      if (layout_.boolValues) walker_.checkBoolBytes(values.data(), values.size(), what);
    }
  }

  // io::readData: a Blosc or zlib chunk (an int64 size, negative for data stored uncompressed),
  // or the raw bytes. Returns the decompressed bytes when they are needed (bool values).
  std::vector<char> walkData(std::uint64_t expected, const std::string& what) {
    using namespace openvdb::io;
    if (!(compression_ & (COMPRESS_BLOSC | COMPRESS_ZIP))) return walker_.bytes(expected, what);
    const bool blosc = compression_ & COMPRESS_BLOSC;
    const std::string kind = blosc ? "Blosc" : "zlib";
    const auto declared =
        walker_.value<std::int64_t>("the size of the " + kind + " chunk of " + what);
    if (declared <= 0) {
      // Stored uncompressed: OpenVDB 10 copies -declared bytes into a buffer of `expected`.
      if (declared == std::numeric_limits<std::int64_t>::min() ||
          std::uint64_t(-declared) != expected) {
        walker_.fail("the " + kind + " chunk of " + what + " declares " +
                     std::to_string(declared == std::numeric_limits<std::int64_t>::min()
                                        ? declared
                                        : -declared) +
                     " uncompressed bytes where the node holds " + std::to_string(expected));
      }
      return walker_.bytes(expected, what);
    }
    walker_.require(std::uint64_t(declared), "the " + kind + " chunk of " + what);
    const std::uint64_t chunkStart = walker_.offset();
    const std::vector<char> chunk = walker_.bytes(std::uint64_t(declared), what);
    if (blosc) {
      std::optional<std::vector<char>> output = bloscDecompressExactly(chunk, expected);
      if (!output) {
        walker_.fail("the Blosc chunk of " + what + " (" + std::to_string(chunk.size()) +
                     " bytes from byte " + std::to_string(chunkStart) +
                     ") is not valid Blosc data decompressing to the node's " +
                     std::to_string(expected) + " bytes");
      }
      return std::move(*output);
    }
    std::vector<char> output;
    output.resize(std::max<std::uint64_t>(expected, 1));
    uLongf produced = static_cast<uLongf>(expected);
    const int status =
        uncompress(reinterpret_cast<Bytef*>(output.data()), &produced,
                   reinterpret_cast<const Bytef*>(chunk.data()), static_cast<uLong>(chunk.size()));
    if (status != Z_OK || produced != expected) {
      walker_.fail("the zlib chunk of " + what + " (" + std::to_string(chunk.size()) +
                   " bytes from byte " + std::to_string(chunkStart) +
                   ") does not decompress to the node's " + std::to_string(expected) + " bytes");
    }
    output.resize(expected);
    return output;
  }

  Walker& walker_;
  const TreeLayout& layout_;
  std::uint32_t compression_;
  bool fromHalf_;
  std::vector<Coord> tiles_;
  std::vector<Coord> leafOrigins_;
  std::uint64_t upperNodes_ = 0, lowerNodes_ = 0, leaves_ = 0, rootEntries_ = 0;
};

// DelayedLoadMetadata::readValue: a leaf count, the per-leaf compression flags and optionally
// the per-leaf compressed sizes, each either Blosc-compressed or raw; `declared` bytes in all.
void walkDelayedLoadMetadata(Walker& walker, std::uint32_t declared, const std::string& what) {
  if (declared == 0) return;  // an empty value: nothing is stored
  const std::uint64_t start = walker.offset();
  const auto count = walker.value<std::uint32_t>("the leaf count of " + what);
  // One flag per leaf, and every leaf takes well over 100 bytes of the file.
  if (count > walker.remaining() / 100) {
    walker.fail(what + " describes " + std::to_string(count) +
                " leaves, more than the rest of the file can hold");
  }
  const auto walkArray = [&](std::uint32_t bytes, std::size_t elementBytes, const char* part) {
    const std::uint64_t expected = std::uint64_t(count) * elementBytes;
    if (bytes == 0) {
      walker.skip(expected, std::string("the ") + part + " of " + what);
      return;
    }
    const std::vector<char> chunk = walker.bytes(bytes, std::string("the ") + part + " of " + what);
    // The writer pads buffers shorter than kBloscPadBytes to that length before compressing.
    std::size_t claimed = 0, compressed = 0, blockSize = 0;
    if (chunk.size() >= BLOSC_MIN_HEADER_LENGTH) {
      blosc_cbuffer_sizes(chunk.data(), &claimed, &compressed, &blockSize);
    }
    const bool padded = expected <= kBloscPadBytes && claimed == kBloscPadBytes;
    if (!bloscDecompressExactly(chunk, padded ? kBloscPadBytes : expected)) {
      walker.fail(std::string("the ") + part + " of " + what +
                  " are not valid Blosc data of the stated leaf count");
    }
  };
  walkArray(walker.value<std::uint32_t>("the size of the leaf flags of " + what), 1, "leaf flags");
  const auto sizesBytes = walker.value<std::uint32_t>("the size of the leaf sizes of " + what);
  if (sizesBytes != kNoCompressedSizes) walkArray(sizesBytes, sizeof(std::int64_t), "leaf sizes");
  const std::uint64_t used = walker.offset() - start;
  if (used > declared) {
    walker.fail(what + " takes " + std::to_string(used) + " bytes but declares " +
                std::to_string(declared));
  }
  walker.skip(declared - used, "the rest of " + what);
}

// MetaMap::readMeta: a count, then per item its name, type name, value size and value.
void walkMetaMap(Walker& walker, const std::string& owner) {
  const auto count = walker.value<std::uint32_t>("the metadata count of " + owner);
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string item =
        "metadata item " + std::to_string(i + 1) + " of " + std::to_string(count) + " of " + owner;
    const std::string name = walker.string("the name of " + item);
    // MetaMap::insertMeta throws on an empty name (openvdb::ValueError, not an I/O error).
    if (name.empty()) walker.fail(item + " has an empty name");
    const std::string what = "metadata '" + name + "' of " + owner;
    const std::string type = walker.string("the type of " + what);
    const auto declared = walker.value<std::uint32_t>("the size of " + what);
    if (!openvdb::Metadata::isRegisteredType(type) || type == "string") {
      walker.skip(declared, "the value of " + what);  // UnknownMetadata, StringMetadata
    } else if (type == openvdb::io::DelayedLoadMetadata::staticTypeName()) {
      walkDelayedLoadMetadata(walker, declared, what);
    } else if (const std::optional<std::size_t> bytes = fixedMetadataBytes(type)) {
      if (declared != *bytes) {
        walker.fail(what + " of type " + type + " declares " + std::to_string(declared) +
                    " bytes instead of " + std::to_string(*bytes));
      }
      const std::vector<char> value = walker.bytes(*bytes, "the value of " + what);
      if (type == "bool") walker.checkBoolBytes(value.data(), value.size(), what);
    } else {
      walker.unsupported(what + " has the type '" + type +
                         "', which OpenVDB registers but d2vdb does not read");
    }
  }
}

// Reads `bytes` of doubles and requires each to be finite.
void walkDoubles(Walker& walker, std::size_t bytes, const std::string& what) {
  const std::vector<char> data = walker.bytes(bytes, what);
  for (std::size_t i = 0; i + sizeof(double) <= data.size(); i += sizeof(double)) {
    double value = 0;
    std::memcpy(&value, data.data() + i, sizeof(double));
    if (!std::isfinite(value)) walker.fail(what + " holds a non-finite number");
  }
}

// Transform::read: the map's type name and its data (a frustum holds a second, linear map).
void walkTransform(Walker& walker, const std::string& owner) {
  const std::string what = "the transform of " + owner;
  const std::string type = walker.string("the map type of " + what);
  if (const std::optional<std::size_t> bytes = linearMapBytes(type)) {
    walkDoubles(walker, *bytes, what);
    return;
  }
  if (type != "NonlinearFrustumMap") {
    walker.fail(what + " has the unknown map type '" + type + "'");
  }
  walkDoubles(walker, 2 * 24 + 2 * 8, "the box, taper and depth of " + what);
  const std::string second = walker.string("the second map type of " + what);
  const std::optional<std::size_t> bytes = linearMapBytes(second);
  if (!bytes) {
    walker.fail(what + " is a frustum whose second map has the type '" + second +
                "' (a linear map was expected)");
  }
  walkDoubles(walker, *bytes, "the second map of " + what);
}

// GridBase::saveFloatAsHalf() of a grid of `type` whose metadata are `metadata` (a MetaMap as
// stored, already checked by walkMetaMap, so OpenVDB can read it safely). Anything OpenVDB still
// refuses in them is reported through `walker`.
bool savedAsHalf(const Walker& walker, const std::string& metadata, const std::string& type) {
  const openvdb::GridBase::Ptr grid = openvdb::GridBase::createGrid(type);
  std::istringstream in(metadata);
  try {
    grid->readMeta(in);
  } catch (const openvdb::Exception& error) {
    walker.fail(std::string("OpenVDB refuses the grid's metadata: ") + error.what());
  }
  return grid->saveFloatAsHalf();
}

const TreeLayout* layoutFor(const std::string& type) {
  for (const TreeLayout& layout : treeLayouts()) {
    if (layout.typeName == type) return &layout;
  }
  return nullptr;
}

}  // namespace

std::vector<VdbGridLayout> checkVdbStream(std::istream& in, std::uint64_t size,
                                          const std::string& name) {
  ensureOpenVdbInitialized();
  Walker walker(in, size, name);

  // Archive::readHeader.
  walker.setContext("the file header");
  const auto magic = walker.value<std::int64_t>("the magic number");
  if (magic != openvdb::OPENVDB_MAGIC) walker.fail("the VDB magic number is missing");
  const auto format = walker.value<std::uint32_t>("the file format version");
  if (format > kNewestFormat) {
    walker.unsupported("file format " + std::to_string(format) + " is newer than the " +
                       std::to_string(kNewestFormat) +
                       " this OpenVDB reads; re-save it with OpenVDB " +
                       std::to_string(openvdb::OPENVDB_LIBRARY_MAJOR_VERSION) + " or older");
  }
  if (format < kOldestFormat) {
    walker.unsupported("file format " + std::to_string(format) + " predates OpenVDB 3.0 (format " +
                       std::to_string(kOldestFormat) +
                       "), which d2vdb does not read; re-save the file with a newer OpenVDB");
  }
  walker.skip(2 * sizeof(std::uint32_t), "the library version");
  const auto hasGridOffsets = walker.value<std::uint8_t>("the grid-offsets flag");
  walker.skip(kUuidBytes, "the file UUID");

  // File metadata and grid count (Stream::Stream).
  walker.setContext("");
  walkMetaMap(walker, "the file");
  const auto gridCount = walker.value<std::int32_t>("the grid count");
  if (gridCount < 0) walker.fail("the grid count is negative (" + std::to_string(gridCount) + ")");

  std::vector<VdbGridLayout> grids;
  for (std::int32_t index = 0; index < gridCount; ++index) {
    walker.setContext("grid " + std::to_string(index + 1) + " of " + std::to_string(gridCount));
    // GridDescriptor::read.
    VdbGridLayout grid;
    grid.name = walker.string("the grid name");
    walker.setContext("grid '" + grid.name + "'");
    std::string type = walker.string("the grid type");
    const std::string halfSuffix = "_HalfFloat";  // GridDescriptor::read strips it
    if (type.size() > halfSuffix.size() &&
        type.compare(type.size() - halfSuffix.size(), halfSuffix.size(), halfSuffix) == 0) {
      type.resize(type.size() - halfSuffix.size());
    }
    grid.type = type;
    const std::string instanceParent = walker.string("the instance parent name");
    const TreeLayout* layout = layoutFor(type);
    if (!layout) {
      const bool registered = openvdb::GridBase::isRegistered(type);
      walker.unsupported("the grid type '" + type + "' " +
                         (registered ? "(a point or other special grid) is not read by d2vdb"
                                     : "is not an OpenVDB grid type") +
                         "; d2vdb reads bool, mask, float, double, int32, int64, vec3s, vec3d and "
                         "vec3i grids");
    }
    const auto gridStart = walker.value<std::int64_t>("the grid start offset");
    const auto blockStart = walker.value<std::int64_t>("the grid data offset");
    const auto gridEnd = walker.value<std::int64_t>("the grid end offset");
    const auto checkOffset = [&](std::int64_t stated, const char* what) {
      if (hasGridOffsets != 0 && stated != static_cast<std::int64_t>(walker.offset())) {
        walker.fail(std::string("the descriptor places the ") + what + " at byte " +
                    std::to_string(stated) + ", but it starts at byte " +
                    std::to_string(walker.offset()));
      }
    };
    checkOffset(gridStart, "grid");

    // Archive::readGrid.
    const auto compression = walker.value<std::uint32_t>("the grid's compression flags");
    const std::uint64_t metadataStart = walker.offset();
    walkMetaMap(walker, "the grid");
    // Half-float storage is whatever the grid's own metadata says once read (GridBase::readMeta
    // replaces the flag the descriptor's "_HalfFloat" suffix set): ask OpenVDB, on the metadata
    // just checked.
    const bool fromHalf = savedAsHalf(walker, walker.bytesSince(metadataStart), type);
    walkTransform(walker, "the grid");
    grid.instance = !instanceParent.empty();
    if (grid.instance) {
      const auto parent = std::find_if(grids.begin(), grids.end(), [&](const VdbGridLayout& g) {
        return g.name == instanceParent && !g.instance;
      });
      if (parent == grids.end() || parent->type != type) {
        walker.fail("the grid shares the tree of '" + instanceParent +
                    "', which is not an earlier grid of the same type");
      }
    } else {
      TreeWalker tree(walker, *layout, compression, fromHalf);
      tree.walkTopology();
      checkOffset(blockStart, "grid's data");
      tree.walkBuffers();
      grid.internalNodes = tree.internalNodes();
      grid.leafNodes = tree.leafNodes();
      grid.treeBytes = tree.treeBytes();
    }
    checkOffset(gridEnd, "grid's end");
    grids.push_back(std::move(grid));
  }
  walker.setContext("");
  if (walker.remaining() > 0) {
    walker.fail(std::to_string(walker.remaining()) + " bytes follow the last grid");
  }
  return grids;
}

}  // namespace d2vdb::detail
