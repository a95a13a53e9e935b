// The budget of smooth tessellations: the vertex count the estimates use against the vertices
// really made, the file estimate against the file written, and the refusal naming the largest
// --lod that fits (found by a linear scan here).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "ManifoldTestSupport.h"
#include "common/ScratchDirectory.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/SmoothTessellation.h"
#include "d2vdb/mesh/MeshIO.h"

namespace d2vdb {
namespace {

class SmoothTessellationBudgetTest : public test::ScratchDirectoryTest {};

TEST_F(SmoothTessellationBudgetTest, CountsAndFileSizesMatchTheTessellation) {
  const auto mesh = test::mixedDegreeMesh().build();
  const LoopLimitSurface loop(mesh);
  const PseudoManifold pps(loop);
  for (const int levels : {0, 1, 2, 3}) {
    const SmoothTessellation t = tessellateSmooth(pps, levels, false);
    EXPECT_EQ(smoothTessellationVertices(*mesh, levels), static_cast<double>(t.mesh.vertexCount()));
  }
  const SmoothTessellation t = tessellateSmooth(pps, 3, false);
  for (const char* name : {"t.obj", "t.ply", "t.stl"}) {
    const std::filesystem::path path = scratch_ / name;
    writeMesh(path, t.mesh);
    const double real = static_cast<double>(std::filesystem::file_size(path));
    MeshFileContents contents;
    contents.normals = true;
    const double estimate =
        estimateMeshFileBytes(meshFormatFromPath(path), smoothTessellationVertices(*mesh, 3),
                              static_cast<double>(t.mesh.triangleCount()), contents);
    EXPECT_GE(estimate, real) << name;
    EXPECT_LE(estimate, 1.5 * real) << name;
  }
}

TEST_F(SmoothTessellationBudgetTest, RefusesNamingTheLargestLevelThatFits) {
  const auto mesh = test::octahedron().build();
  ResourceBudget budget;
  budget.maxOutputBytes = 2'000'000;
  int largest = -1;
  for (int level = 0; level <= 10; ++level) {
    MeshFileContents contents;
    contents.normals = true;
    const double bytes = estimateMeshFileBytes(
        MeshFormat::Obj, smoothTessellationVertices(*mesh, level),
        static_cast<double>(smoothTessellationTriangles(*mesh, level)), contents);
    if (bytes <= 2e6 && estimateSmoothTessellationMemoryBytes(*mesh, level, false) <=
                            static_cast<double>(budget.maxMemoryBytes)) {
      largest = level;
    }
  }
  ASSERT_GT(largest, 0);
  EXPECT_NO_THROW(enforceSmoothTessellationBudget(*mesh, largest, false, MeshFormat::Obj, budget));
  try {
    enforceSmoothTessellationBudget(*mesh, 10, false, MeshFormat::Obj, budget);
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("(--lod)"), std::string::npos) << message;
    EXPECT_NE(message.find("--max-output"), std::string::npos) << message;
    EXPECT_NE(message.find("use --lod " + std::to_string(largest) + " or lower"), std::string::npos)
        << message;
  }
}

}  // namespace
}  // namespace d2vdb
