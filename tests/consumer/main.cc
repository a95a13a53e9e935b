// A downstream program built against an installed d2vdb: reads a level set and reports on it.
#include <iostream>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/Version.h"
#include "d2vdb/io/VdbFile.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: consumer FILE.vdb\n";
    return 1;
  }
  try {
    const openvdb::FloatGrid::Ptr grid = d2vdb::readLevelSet(argv[1]);
    std::cout << "d2vdb " << d2vdb::kVersion << ": " << grid->getName() << " has "
              << grid->activeVoxelCount() << " active voxels\n";
    return grid->activeVoxelCount() > 0 ? 0 : 1;
  } catch (const d2vdb::Error& error) {
    std::cerr << "error: " << error.what() << '\n';
    return 2;
  }
}
