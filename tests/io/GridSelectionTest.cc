// selectGrid()/findGrid(): the one rule for which grid of a .vdb file a command uses, checked on
// hand-built grid lists where the expected choice is known.
#include "d2vdb/io/GridSelection.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/IoTestSupport.h"

namespace d2vdb {
namespace {

using test::expectInputError;

template <typename GridT>
openvdb::GridBase::Ptr makeGrid(const std::string& name, bool levelSet = false) {
  typename GridT::Ptr grid = GridT::create();
  grid->setName(name);
  if (levelSet) grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

TEST(GridSelection, NamedGridElseFirstLevelSetElseFirstScalarGrid) {
  const std::vector<openvdb::GridBase::Ptr> grids = {
      makeGrid<openvdb::Vec3SGrid>("velocity"),
      makeGrid<openvdb::DoubleGrid>("temperature"),
      makeGrid<openvdb::FloatGrid>("density"),
      nullptr,
      makeGrid<openvdb::DoubleGrid>("double_surface", true),
      makeGrid<openvdb::FloatGrid>("surface", true),
      makeGrid<openvdb::FloatGrid>("inner", true)};
  // No name: the first level set of an accepted type, then the first grid of one.
  EXPECT_EQ(findGrid(grids)->getName(), "surface");
  EXPECT_EQ(findGrid(grids, "", ScalarGridTypes::FloatOrDouble)->getName(), "double_surface");
  const std::vector<openvdb::GridBase::Ptr> noLevelSet(grids.begin(), grids.begin() + 4);
  EXPECT_EQ(findGrid(noLevelSet)->getName(), "density");
  EXPECT_EQ(findGrid(noLevelSet, "", ScalarGridTypes::FloatOrDouble)->getName(), "temperature");
  // A name wins over the rule, if its type is accepted.
  EXPECT_EQ(selectGrid(grids, "'f.vdb'", "inner")->getName(), "inner");
  EXPECT_EQ(selectGrid(grids, "'f.vdb'", "temperature", ScalarGridTypes::FloatOrDouble)->getName(),
            "temperature");
  EXPECT_EQ(findGrid(grids, "temperature"), nullptr);
  EXPECT_EQ(findGrid(grids, "velocity", ScalarGridTypes::FloatOrDouble), nullptr);
  EXPECT_EQ(findGrid(grids, "absent"), nullptr);
  EXPECT_EQ(findGrid({}), nullptr);
}

TEST(GridSelection, ErrorsSayWhyAndListTheGrids) {
  const std::vector<openvdb::GridBase::Ptr> grids = {
      makeGrid<openvdb::Vec3SGrid>("velocity"), makeGrid<openvdb::DoubleGrid>("temperature", true)};
  expectInputError([&] { selectGrid(grids, "'f.vdb'"); },
                   {"'f.vdb' holds no float grid",
                    "'velocity' (vec3s, unknown), 'temperature' (double, level set)"});
  expectInputError(
      [&] { selectGrid(grids, "'f.vdb'", "velocity", ScalarGridTypes::FloatOrDouble); },
      {"grid 'velocity' in 'f.vdb' holds vec3s values", "a float or double grid is needed"});
  expectInputError([&] { selectGrid(grids, "'f.vdb'", "surface"); },
                   {"'f.vdb' has no grid named 'surface'", "its grids are: 'velocity'"});
  EXPECT_EQ(describeGrids({}), "none");
}

}  // namespace
}  // namespace d2vdb
