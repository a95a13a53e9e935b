// Corrupt .vdb data must be rejected with InputError before OpenVDB acts on it: chunk sizes that
// disagree with the node (which made OpenVDB 10 write past its buffers), lengths beyond the end
// of the data (which made it allocate gigabytes), inconsistent tree structure, duplicated bytes.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/io/VdbFile.h"
#include "d2vdb/io/detail/VdbFormatCheck.h"
#include "d2vdb/io/detail/VdbStream.h"
#include "io/IoTestSupport.h"

namespace d2vdb {
namespace {

using test::expectInputError;

class VdbCorruptionTest : public test::ScratchDirectoryTest {
 protected:
  // A small sphere level set written by writeVdb (Blosc unless `blosc` is false), as bytes.
  std::string sphereFile(bool blosc = true, bool half = false) {
    const openvdb::FloatGrid::Ptr grid =
        primitiveLevelSet(Sphere({0.0, 0.0, 0.0}, 1.0), {0.125, 3.0});
    VdbWriteOptions options;
    options.blosc = blosc;
    options.halfFloat = half;
    writeVdb(file("sphere.vdb"), {grid}, options);
    std::ifstream in(file("sphere.vdb"), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  static std::vector<openvdb::GridBase::Ptr> read(const std::string& bytes) {
    std::istringstream in(bytes);
    return detail::readVdbStream(in, bytes.size(), "corrupt.vdb");
  }

  // Offsets of the size words of the Blosc chunks: an int64 n followed by a Blosc header whose
  // compressed size (bytes 12-15) is n.
  static std::vector<std::size_t> bloscChunks(const std::string& bytes) {
    std::vector<std::size_t> offsets;
    for (std::size_t p = 0; p + 24 <= bytes.size(); ++p) {
      std::int64_t size = 0;
      std::uint32_t compressed = 0;
      std::memcpy(&size, bytes.data() + p, 8);
      std::memcpy(&compressed, bytes.data() + p + 8 + 12, 4);
      if (size > 16 && size < 100000 && std::int64_t(compressed) == size &&
          (bytes[p + 8] == 1 || bytes[p + 8] == 2)) {
        offsets.push_back(p);
      }
    }
    return offsets;
  }

  template <typename T>
  static void put(std::string& bytes, std::size_t offset, T value) {
    std::memcpy(bytes.data() + offset, &value, sizeof(T));
  }
};

TEST_F(VdbCorruptionTest, ValidFilesPassTheWalkInEveryEncoding) {
  for (const bool blosc : {true, false}) {
    for (const bool half : {false, true}) {
      SCOPED_TRACE(std::string(blosc ? "blosc" : "raw") + (half ? " half" : ""));
      const std::string bytes = sphereFile(blosc, half);
      std::istringstream in(bytes);
      const std::vector<detail::VdbGridLayout> layout =
          detail::checkVdbStream(in, bytes.size(), "sphere.vdb");
      ASSERT_EQ(layout.size(), 1u);
      const std::vector<openvdb::GridBase::Ptr> grids = read(bytes);
      ASSERT_EQ(grids.size(), 1u);
      // The walk counted the nodes OpenVDB then built.
      const auto& tree = openvdb::gridConstPtrCast<openvdb::FloatGrid>(grids[0])->tree();
      EXPECT_EQ(layout[0].leafNodes, tree.leafCount());
      EXPECT_EQ(layout[0].internalNodes, tree.nonLeafCount() - 1);  // nonLeafCount counts the root
      EXPECT_GE(layout[0].treeBytes, tree.memUsage() / 2);
      EXPECT_LE(layout[0].treeBytes, tree.memUsage() * 2);
    }
  }
}

TEST_F(VdbCorruptionTest, ChunkSizesThatDisagreeWithTheNodeAreRejected) {
  const std::string valid = sphereFile();
  const std::vector<std::size_t> chunks = bloscChunks(valid);
  ASSERT_GT(chunks.size(), 10u);
  const std::size_t chunk = chunks[chunks.size() / 2];
  std::int64_t stated = 0;
  std::memcpy(&stated, valid.data() + chunk, 8);

  // The high word overwritten: a negative size, "stored uncompressed", larger than the node (this
  // made OpenVDB 10.0 copy the rest of the file into a 2 KB leaf buffer).
  std::string negative = valid;
  put<std::uint32_t>(negative, chunk + 4, 0xC0000000u);
  expectInputError([&] { read(negative); }, {"corrupt.vdb", "uncompressed bytes where the node"});
  // The low word overwritten: a gigabyte chunk in a 20 KB file.
  std::string huge = valid;
  put<std::uint32_t>(huge, chunk, 0x40000000u);
  expectInputError([&] { read(huge); }, {"bytes but only", "remain"});
  // A size that is plausible but not the chunk's: the Blosc header disagrees.
  std::string shorter = valid;
  put<std::int64_t>(shorter, chunk, stated - 1);
  expectInputError([&] { read(shorter); }, {"not valid Blosc data"});
  // The Blosc header claims more uncompressed bytes than the node holds.
  std::string claim = valid;
  put<std::uint32_t>(claim, chunk + 8 + 4, 1u << 20);
  expectInputError([&] { read(claim); }, {"not valid Blosc data"});
}

TEST_F(VdbCorruptionTest, LengthsBeyondTheDataAreRejectedBeforeAllocating) {
  const std::string valid = sphereFile();
  // The file metadata's first name length (after magic, version, library version, the offsets
  // flag, the UUID and the metadata count).
  const std::size_t firstName = 8 + 4 + 8 + 1 + 36 + 4;
  std::string name = valid;
  put<std::uint32_t>(name, firstName, 0xFFFFFFF0u);
  expectInputError([&] { read(name); }, {"the name of metadata item 1", "needs 4294967280 bytes"});
  // A metadata count of four billion.
  std::string count = valid;
  put<std::uint32_t>(count, firstName - 4, 0xFFFFFFFFu);
  expectInputError([&] { read(count); }, {"corrupt.vdb"});
  // A grid count of two billion, and a negative one.
  const std::size_t gridCount = valid.find("surface") - 8;  // before the grid name's length
  std::string grids = valid;
  put<std::int32_t>(grids, gridCount, 2000000000);
  expectInputError([&] { read(grids); }, {"corrupt.vdb"});
  put<std::int32_t>(grids, gridCount, -5);
  expectInputError([&] { read(grids); }, {"grid count is negative"});
}

TEST_F(VdbCorruptionTest, DuplicatedOrOverwrittenBytesNeverReachOpenVdb) {
  // Any change to a file's structure must give InputError (or, within values and strings, a
  // file that reads); never a crash. ASan runs make this a memory-safety test.
  const std::string valid = sphereFile();
  std::mt19937 random(2024);
  std::uniform_int_distribution<std::size_t> position(0, valid.size() - 9);
  int rejected = 0, read_ = 0;
  for (int trial = 0; trial < 150; ++trial) {
    std::string bytes = valid;
    const std::size_t at = position(random);
    if (trial % 3 == 0) {
      bytes.insert(at, valid.substr(at, 1 + trial % 7));  // a few bytes duplicated
    } else {
      const std::uint32_t words[] = {0x40000000u, 0xC0000000u, 0xFFFFFFFFu, 0u, 7u};
      put<std::uint32_t>(bytes, at, words[trial % 5]);
    }
    try {
      read(bytes);
      ++read_;
    } catch (const InputError&) {
      ++rejected;
    }
  }
  EXPECT_GT(rejected, 50);
  EXPECT_EQ(rejected + read_, 150);
  // A duplicated byte anywhere shifts what follows: always rejected.
  for (std::size_t at = 0; at < valid.size(); at += valid.size() / 40) {
    std::string bytes = valid;
    bytes.insert(at, 1, bytes[at]);
    expectInputError([&] { read(bytes); }, {"corrupt.vdb"});
  }
}

TEST_F(VdbCorruptionTest, InconsistentTreesAndTrailingBytesAreRejected) {
  const std::string valid = sphereFile(/*blosc=*/false);
  expectInputError([&] { read(valid + std::string(3, '\0')); }, {"3 bytes follow the last grid"});

  // The tree starts after the transform: the buffer count (int32 1), the background, the tile
  // and child counts, then the first child's origin.
  const std::size_t map = valid.find("UniformScaleMap");
  ASSERT_NE(map, std::string::npos);
  const std::size_t tree = map + std::string("UniformScaleMap").size() + 5 * 24;
  std::int32_t bufferCount = 0;
  std::memcpy(&bufferCount, valid.data() + tree, 4);
  ASSERT_EQ(bufferCount, 1);
  const std::size_t childCount = tree + 4 + 4 + 4;
  const std::size_t firstOrigin = childCount + 4;

  std::string children = valid;
  put<std::uint32_t>(children, childCount, 0x7FFFFFFFu);
  expectInputError([&] { read(children); }, {"corrupt.vdb"});
  std::string unaligned = valid;
  put<std::int32_t>(unaligned, firstOrigin, 17);
  expectInputError([&] { read(unaligned); }, {"not aligned to the root's grid"});
  std::string far = valid;
  put<std::int32_t>(far, firstOrigin, 2147479552);  // 2^31 - 4096
  expectInputError([&] { read(far); }, {"beyond +-2^30 voxels"});
  std::string buffers = valid;
  put<std::int32_t>(buffers, tree, 2);
  expectInputError([&] { read(buffers); }, {"buffer count is 2"});

  // A transform whose stored inverse does not undo it.
  std::string inverse = valid;
  const std::size_t inverseScale = map + std::string("UniformScaleMap").size() + 2 * 24;
  put<double>(inverse, inverseScale, 3.0);
  expectInputError([&] { read(inverse); }, {"unusable transform"});
  std::string nan = valid;
  put<double>(nan, inverseScale, std::numeric_limits<double>::quiet_NaN());
  expectInputError([&] { read(nan); }, {"non-finite number"});
}

TEST_F(VdbCorruptionTest, OldAndNewFormatsAreNamed) {
  std::string bytes = sphereFile();
  put<std::uint32_t>(bytes, 8, 221);
  expectInputError([&] { read(bytes); }, {"file format 221 predates OpenVDB 3.0"});
  put<std::uint32_t>(bytes, 8, 300);
  expectInputError([&] { read(bytes); }, {"file format 300 is newer"});
}

}  // namespace
}  // namespace d2vdb
