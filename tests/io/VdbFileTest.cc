// .vdb reading and writing: exact round trips, half floats, interoperability with vdb_print,
// metadata conventions, and rejection of missing, truncated, corrupt and non-finite files.
#include "d2vdb/io/VdbFile.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <random>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/Version.h"
#include "d2vdb/field/Primitives.h"
#include "field/FieldTestSupport.h"
#include "io/IoTestSupport.h"

namespace d2vdb {
namespace {

class VdbFileTest : public test::ScratchDirectoryTest {
 protected:
  static openvdb::FloatGrid::Ptr torusLevelSet() {
    const Torus torus({0.1, -0.05, 0.02}, 1.0, 0.35);
    openvdb::FloatGrid::Ptr grid = primitiveLevelSet(torus, {0.05, 3.0});
    grid->setName("");  // let the writer name it
    return grid;
  }

  // Expects InputError whose message contains `text`.
  template <typename Call>
  static void expectInputError(Call&& call, const std::string& text) {
    test::expectInputError(std::forward<Call>(call), {text});
  }
};

TEST_F(VdbFileTest, RoundTripIsExactWithAndWithoutBlosc) {
  const openvdb::FloatGrid::Ptr original = torusLevelSet();
  original->insertMeta("user_note", openvdb::StringMetadata("kept"));
  for (const bool blosc : {true, false}) {
    SCOPED_TRACE(blosc ? "blosc" : "uncompressed");
    const std::filesystem::path path = file(blosc ? "blosc.vdb" : "plain.vdb");
    VdbWriteOptions options;
    options.blosc = blosc;
    options.source = "torus.json";
    writeVdb(path, {original}, options);

    const std::vector<openvdb::GridBase::Ptr> grids = readAllGrids(path);
    ASSERT_EQ(grids.size(), 1u);
    const auto read = openvdb::gridPtrCast<openvdb::FloatGrid>(grids[0]);
    ASSERT_TRUE(read);
    test::expectBitwiseIdentical(*original, *read);
    EXPECT_EQ(read->getName(), "surface");
    EXPECT_EQ(read->getCreator(), std::string("d2vdb ") + kVersion);
    EXPECT_EQ(read->metaValue<std::string>(kSourceMetadata), "torus.json");
    EXPECT_DOUBLE_EQ(read->metaValue<double>(kHalfWidthMetadata), 3.0);  // background / voxel
    EXPECT_EQ(read->metaValue<std::string>("user_note"), "kept");
    EXPECT_FALSE(read->saveFloatAsHalf());
    const std::string compression =
        read->metaValue<std::string>(openvdb::GridBase::META_FILE_COMPRESSION);
    EXPECT_EQ(compression.find("blosc") != std::string::npos, blosc) << compression;
  }
  // The caller's grid was not modified by writing.
  EXPECT_EQ(original->getName(), "");
  EXPECT_FALSE((*original)[openvdb::GridBase::META_GRID_CREATOR]);
}

TEST_F(VdbFileTest, SeveralGridsKeepOrderTypesAndSharedTopology) {
  const openvdb::FloatGrid::Ptr surface = torusLevelSet();
  // A vector grid with the level set's topology, holding each voxel's index as a vector.
  const openvdb::Vec3SGrid::Ptr vectors = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  vectors->setTransform(surface->transform().copy());
  vectors->tree().topologyUnion(surface->tree());
  for (auto voxel = vectors->beginValueOn(); voxel; ++voxel) {
    const openvdb::Coord ijk = voxel.getCoord();
    voxel.setValue(openvdb::Vec3s(float(ijk.x()), float(ijk.y()), 0.5f * float(ijk.z())));
  }
  vectors->setName("footpoint");
  const openvdb::Int32Grid::Ptr labels = openvdb::Int32Grid::create(-1);
  labels->tree().setValue(openvdb::Coord(1, 2, 3), 42);
  labels->setName("labels");

  const std::filesystem::path path = file("three.vdb");
  VdbWriteOptions options;
  options.halfWidth = 3.0;
  writeVdb(path, {labels, vectors, surface}, options);

  const std::vector<openvdb::GridBase::Ptr> grids = readAllGrids(path);
  ASSERT_EQ(grids.size(), 3u);
  EXPECT_EQ(grids[0]->getName(), "labels");
  EXPECT_EQ(grids[1]->getName(), "footpoint");
  EXPECT_EQ(grids[2]->getName(), "surface");
  const auto readLabels = openvdb::gridPtrCast<openvdb::Int32Grid>(grids[0]);
  ASSERT_TRUE(readLabels);
  EXPECT_EQ(readLabels->tree().getValue(openvdb::Coord(1, 2, 3)), 42);
  EXPECT_EQ(readLabels->activeVoxelCount(), 1u);
  const auto readVectors = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grids[1]);
  ASSERT_TRUE(readVectors);
  EXPECT_TRUE(readVectors->tree().hasSameTopology(surface->tree()));
  for (auto voxel = readVectors->cbeginValueOn(); voxel; ++voxel) {
    const openvdb::Coord ijk = voxel.getCoord();
    ASSERT_EQ(*voxel, openvdb::Vec3s(float(ijk.x()), float(ijk.y()), 0.5f * float(ijk.z())));
  }
  // readLevelSet finds the level set although it is not the first grid.
  const openvdb::FloatGrid::Ptr level = readLevelSet(path);
  EXPECT_EQ(level->getName(), "surface");
  test::expectBitwiseIdentical(*surface, *level);
  EXPECT_EQ(readLevelSet(path, "surface")->getName(), "surface");
}

TEST_F(VdbFileTest, HalfFloatRoundTripIsWithinHalfPrecision) {
  const openvdb::FloatGrid::Ptr original = torusLevelSet();
  const std::filesystem::path path = file("half.vdb");
  VdbWriteOptions options;
  options.blosc = false;  // so that the file sizes compare the value storage directly
  writeVdb(file("full.vdb"), {original}, options);
  options.halfFloat = true;
  writeVdb(path, {original}, options);
  EXPECT_LT(std::filesystem::file_size(path), std::filesystem::file_size(file("full.vdb")));
  const openvdb::FloatGrid::Ptr read = readLevelSet(path);
  EXPECT_TRUE(read->saveFloatAsHalf());
  ASSERT_TRUE(read->tree().hasSameTopology(original->tree()));
  const auto accessor = read->getConstAccessor();
  double largestRelative = 0.0;
  for (auto voxel = original->cbeginValueOn(); voxel; ++voxel) {
    const float expected = *voxel;
    const float got = accessor.getValue(voxel.getCoord());
    // Half floats keep 11 significant bits: round-to-nearest errs by at most 2^-11 relative
    // (normal range) or 2^-25 absolute (subnormal range, below 6.1e-5).
    EXPECT_LE(std::abs(got - expected), std::abs(expected) * 0x1p-11f + 0x1p-25f)
        << "at " << voxel.getCoord() << ": " << expected << " became " << got;
    if (std::abs(expected) > 1e-3f) {
      largestRelative =
          std::max(largestRelative, double(std::abs(got - expected) / std::abs(expected)));
    }
  }
  EXPECT_GT(largestRelative, 0.0);  // the values really went through half precision
  // The background goes through half precision too.
  EXPECT_NEAR(read->background(), original->background(), original->background() * 0x1p-11f);
}

TEST_F(VdbFileTest, VdbPrintReadsWhatWeWrite) {
  const std::filesystem::path path = file("print me.vdb");
  writeVdb(path, {torusLevelSet()});
  const std::string command = std::string(D2VDB_VDB_PRINT) + " -l '" + path.string() + "' 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(command.c_str(), "r"), ::pclose);
  ASSERT_TRUE(pipe);
  std::string output;
  char buffer[4096];
  std::size_t count = 0;
  while ((count = std::fread(buffer, 1, sizeof(buffer), pipe.get())) > 0)
    output.append(buffer, count);
  const int status = ::pclose(pipe.release());
  EXPECT_EQ(status, 0) << output;
  EXPECT_NE(output.find("Name: surface"), std::string::npos) << output;
  EXPECT_NE(output.find("class: level set"), std::string::npos) << output;
  EXPECT_NE(output.find(std::string("creator: d2vdb ") + kVersion), std::string::npos) << output;
  EXPECT_NE(output.find("d2vdb_half_width: 3"), std::string::npos) << output;
}

TEST_F(VdbFileTest, ReadsLevelSetsWrittenByPlainOpenVdb) {
  // A file as another OpenVDB tool would write it: zip compression, a fog volume first, no
  // d2vdb metadata, a level set under another name.
  const openvdb::FloatGrid::Ptr fog = openvdb::FloatGrid::create(0.0f);
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  fog->setName("density");
  fog->tree().setValue(openvdb::Coord(0, 0, 0), 0.5f);
  const openvdb::FloatGrid::Ptr levelSet = torusLevelSet();
  levelSet->setName("ls_torus");
  {
    openvdb::io::File other(file("other.vdb").string());
    other.setCompression(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
    other.write(openvdb::GridPtrVec{fog, levelSet});
    other.close();
  }
  const openvdb::FloatGrid::Ptr read = readLevelSet(file("other.vdb"));
  EXPECT_EQ(read->getName(), "ls_torus");
  test::expectBitwiseIdentical(*levelSet, *read);
  // By name, any float grid can be had; the first float grid is the fallback without a level set.
  EXPECT_EQ(readLevelSet(file("other.vdb"), "density")->getGridClass(), openvdb::GRID_FOG_VOLUME);
  {
    openvdb::io::File fogOnly(file("fog.vdb").string());
    fogOnly.write(openvdb::GridPtrVec{fog});
    fogOnly.close();
  }
  EXPECT_EQ(readLevelSet(file("fog.vdb"))->getName(), "density");
}

TEST_F(VdbFileTest, DescribeSummarizesEachGrid) {
  const openvdb::FloatGrid::Ptr grid = torusLevelSet();
  const std::filesystem::path path = file("info.vdb");
  writeVdb(path, {grid});
  const std::vector<VdbGridInfo> infos = describeVdbFile(path);
  ASSERT_EQ(infos.size(), 1u);
  const VdbGridInfo& info = infos[0];
  EXPECT_EQ(info.name, "surface");
  EXPECT_EQ(info.valueType, "float");
  EXPECT_EQ(info.gridClass, "level set");
  EXPECT_EQ(info.voxelSize, openvdb::Vec3d(0.05));
  EXPECT_EQ(info.activeVoxelCount, grid->activeVoxelCount());
  EXPECT_EQ(info.indexBoundingBox, grid->evalActiveVoxelBoundingBox());
  // The torus (R 1, r 0.35, centre (0.1, -0.05, 0.02)) reaches x = 1.45 + 0.1 plus the band.
  EXPECT_NEAR(info.worldBoundingBox.max().x(), 0.1 + 1.35 + 0.15, 0.05 + 1e-9);
  EXPECT_NEAR(info.worldBoundingBox.min().z(), 0.02 - 0.35 - 0.15, 0.05 + 1e-9);
  EXPECT_GT(info.memoryBytes, info.activeVoxelCount * sizeof(float));
  bool sawCreator = false;
  for (const auto& [name, value] : info.metadata) {
    if (name == "creator") sawCreator = (value == std::string("d2vdb ") + kVersion);
  }
  EXPECT_TRUE(sawCreator);
}

TEST_F(VdbFileTest, WriterNamesUnnamedGridsAndRejectsBadRequests) {
  const openvdb::FloatGrid::Ptr first = torusLevelSet();
  const openvdb::FloatGrid::Ptr second = torusLevelSet();
  const openvdb::FloatGrid::Ptr fog = openvdb::FloatGrid::create(0.0f);
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  const std::filesystem::path path = file("names.vdb");
  writeVdb(path, {first, second, fog});
  const auto grids = readAllGrids(path);
  ASSERT_EQ(grids.size(), 3u);
  EXPECT_EQ(grids[0]->getName(), "surface");
  EXPECT_EQ(grids[1]->getName(), "surface_2");
  EXPECT_EQ(grids[2]->getName(), "grid_2");
  EXPECT_FALSE((*grids[2])[kHalfWidthMetadata]);  // not a level set, no half-width given

  expectInputError([&] { writeVdb(file("none.vdb"), {}); }, "no grids");
  expectInputError([&] { writeVdb(file("null.vdb"), {first, nullptr}); }, "null");
  const openvdb::FloatGrid::Ptr a = torusLevelSet();
  const openvdb::FloatGrid::Ptr b = torusLevelSet();
  a->setName("same");
  b->setName("same");
  expectInputError([&] { writeVdb(file("dup.vdb"), {a, b}); }, "two grids are named 'same'");
  // Point data grids are registered by OpenVDB but are not a standard volume type for us.
  const std::string pointType = "ptdataidx32_5_4_3";
  openvdb::GridBase::Ptr points;
  for (const std::string& type : {"Tree_" + pointType, pointType}) {
    if (openvdb::GridBase::isRegistered(type)) points = openvdb::GridBase::createGrid(type);
  }
  ASSERT_TRUE(points) << "OpenVDB's point data grid type is not registered";
  expectInputError([&] { writeVdb(file("points.vdb"), {points}); }, "not a standard");
  EXPECT_FALSE(std::filesystem::exists(file("points.vdb")));
  // Writing into a missing directory fails as a runtime failure, leaving nothing behind.
  EXPECT_THROW(writeVdb(file("missing") / "x.vdb", {first}), RuntimeFailure);
}

TEST_F(VdbFileTest, RejectsMissingEmptyAndNonVdbFiles) {
  expectInputError([&] { readLevelSet(file("absent.vdb")); }, "does not exist");
  test::writeWholeFile(file("empty.vdb"), "");
  expectInputError([&] { readLevelSet(file("empty.vdb")); }, "is empty");
  std::mt19937 random(7);
  std::string noise(4096, '\0');
  for (char& c : noise) c = static_cast<char>(random() & 0xff);
  test::writeWholeFile(file("noise.vdb"), noise);
  expectInputError([&] { readLevelSet(file("noise.vdb")); }, "not a .vdb file");
  expectInputError([&] { readAllGrids(scratch_); }, "not a regular file");
  // The magic number followed by noise.
  std::string magicThenNoise = test::readWholeFile([&] {
                                 writeVdb(file("valid.vdb"), {torusLevelSet()});
                                 return file("valid.vdb");
                               }())
                                   .substr(0, 8) +
                               noise;
  test::writeWholeFile(file("magic-noise.vdb"), magicThenNoise);
  EXPECT_THROW(readAllGrids(file("magic-noise.vdb")), InputError);
}

TEST_F(VdbFileTest, RejectsTruncatedFilesAtEveryCut) {
  const openvdb::FloatGrid::Ptr surface = torusLevelSet();
  const openvdb::Vec3SGrid::Ptr vectors = openvdb::Vec3SGrid::create(openvdb::Vec3s(1.0f));
  vectors->tree().topologyUnion(surface->tree());
  vectors->setName("vectors");
  writeVdb(file("whole.vdb"), {surface, vectors});
  const std::string whole = test::readWholeFile(file("whole.vdb"));
  ASSERT_GT(whole.size(), 10000u);
  std::vector<std::size_t> cuts = {whole.size() / 10, whole.size() / 2, whole.size() * 9 / 10,
                                   whole.size() - 1};
  for (std::size_t cut = 9; cut < 400; cut += 7) cuts.push_back(cut);  // header and metadata
  for (std::size_t i = 1; i < 40; ++i) cuts.push_back(whole.size() * i / 40);
  for (const std::size_t cut : cuts) {
    SCOPED_TRACE("truncated to " + std::to_string(cut) + " of " + std::to_string(whole.size()));
    test::writeWholeFile(file("cut.vdb"), whole.substr(0, cut));
    expectInputError([&] { readAllGrids(file("cut.vdb")); }, "cut.vdb");
  }
  test::writeWholeFile(file("cut.vdb"), whole.substr(0, whole.size() / 2));
  expectInputError([&] { readLevelSet(file("cut.vdb")); }, "truncated");
}

TEST_F(VdbFileTest, RejectsFilesWithoutAFloatGrid) {
  const openvdb::Int32Grid::Ptr labels = openvdb::Int32Grid::create(0);
  labels->setName("labels");
  labels->tree().setValue(openvdb::Coord(0, 0, 0), 5);
  writeVdb(file("ints.vdb"), {labels});
  EXPECT_EQ(readAllGrids(file("ints.vdb")).size(), 1u);
  expectInputError([&] { readLevelSet(file("ints.vdb")); }, "'labels' (int32");
  expectInputError([&] { readLevelSet(file("ints.vdb"), "labels"); }, "holds int32 values");
  expectInputError([&] { readLevelSet(file("ints.vdb"), "surface"); }, "no grid named 'surface'");
}

TEST_F(VdbFileTest, RejectsNonFiniteValues) {
  const openvdb::FloatGrid::Ptr grid = torusLevelSet();
  grid->tree().setValue(openvdb::Coord(25, 0, 0), std::numeric_limits<float>::quiet_NaN());
  writeVdb(file("nan.vdb"), {grid});
  expectInputError([&] { readLevelSet(file("nan.vdb")); },
                   "1 non-finite value, e.g. nan at active voxel (25, 0, 0)");

  const openvdb::FloatGrid::Ptr tiles = torusLevelSet();
  tiles->tree().addTile(1, openvdb::Coord(800, 800, 800), std::numeric_limits<float>::infinity(),
                        false);
  writeVdb(file("inf.vdb"), {tiles});
  expectInputError([&] { readAllGrids(file("inf.vdb")); },
                   "inf at the tile starting at index (800, 800, 800)");
}

}  // namespace
}  // namespace d2vdb
