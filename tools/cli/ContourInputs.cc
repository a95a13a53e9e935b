#include "ContourInputs.h"

#include "d2vdb/io/InputFile.h"

namespace d2vdb::cli {

void declareIsoAndGridOptions(CLI::App& command, double& isoValue, std::string& gridName) {
  command.add_option("--iso", isoValue, "Iso-value (grid value units)")->capture_default_str();
  command.add_option("--grid", gridName,
                     "Name of the grid (default: the first float/double level set)");
}

openvdb::GridBase::Ptr loadContourGrid(const std::string& input, const std::string& gridName,
                                       const std::string& commandName) {
  LoadOptions load;
  load.purpose = "the input of 'd2vdb " + commandName + "'";
  load.gridName = gridName;
  load.gridTypes = ScalarGridTypes::FloatOrDouble;
  return loadInputAs<LevelSetInput>(input, load).grid;
}

}  // namespace d2vdb::cli
