// estimateMeshFileBytes() against the bytes writeMesh() really writes, for every format and
// encoding, with and without normals, colours and scalars: never below, and within the stated
// factor (1.5 for text; binary exact up to the header).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "d2vdb/mesh/MeshIO.h"
#include "mesh/MeshTestSupport.h"

namespace d2vdb {
namespace {

namespace fs = std::filesystem;

class MeshFileEstimateTest : public test::ScratchDirectoryTest {};

TEST_F(MeshFileEstimateTest, EstimatesBoundTheWrittenBytes) {
  TriangleMesh plain = test::torus(40, 60);  // 2400 vertices, 4800 triangles, coordinates ~1
  TriangleMesh withNormals = plain;
  for (const Eigen::Vector3f& p : plain.positions) {
    withNormals.normals.push_back((p + Eigen::Vector3f(0.1f, -0.2f, 0.3f)).normalized());
  }
  VertexAttributes attributes;
  attributes.scalarName = "distance";
  for (std::size_t v = 0; v < plain.positions.size(); ++v) {
    attributes.scalars.push_back(0.001f * static_cast<float>(v) - 1.1f);
    attributes.colors.push_back({static_cast<std::uint8_t>(v % 256), 77, 255});
  }
  attributes.moreScalars.push_back({"k1", attributes.scalars});
  struct Case {
    std::string name;
    bool binary;
  };
  for (const Case& c : {Case{"m.obj", true}, Case{"m.ply", true}, Case{"a.ply", false},
                        Case{"m.stl", true}, Case{"a.stl", false}}) {
    for (const bool normals : {false, true}) {
      for (const bool withAttributes : {false, true}) {
        const TriangleMesh& mesh = normals ? withNormals : plain;
        const fs::path path = scratch_ / c.name;
        MeshWriteOptions options;
        options.binary = c.binary;
        writeMesh(path, mesh, withAttributes ? attributes : VertexAttributes{}, options);
        const MeshFormat format = meshFormatFromPath(path);
        MeshFileContents contents;
        contents.normals = normals && format != MeshFormat::Stl;
        contents.colors = withAttributes && format != MeshFormat::Stl;
        contents.scalars = withAttributes && format == MeshFormat::Ply ? 2 : 0;
        const double real = static_cast<double>(fs::file_size(path));
        const double estimate =
            estimateMeshFileBytes(format, static_cast<double>(mesh.vertexCount()),
                                  static_cast<double>(mesh.triangleCount()), contents, options);
        const std::string what = c.name + (normals ? " normals" : "") +
                                 (withAttributes ? " attributes" : "") + ": real " +
                                 std::to_string(real) + ", estimate " + std::to_string(estimate);
        EXPECT_GE(estimate, real) << what;
        if (c.binary && format != MeshFormat::Obj) {
          EXPECT_LE(estimate, real + 512.0) << what;  // exact up to the header
        } else {
          EXPECT_LE(estimate, 1.5 * real) << what;
        }
      }
    }
  }
}

}  // namespace
}  // namespace d2vdb
