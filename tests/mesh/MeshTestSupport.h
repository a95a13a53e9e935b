// Shared helpers for the mesh tests: hand-built meshes with known topology and byte-level file
// assembly, plus the scratch directory, file helpers and InputError checks of tests/support.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include "common/AppendMesh.h"
#include "common/ExpectInputError.h"
#include "common/ScratchDirectory.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/mesh/TriangleMesh.h"

namespace d2vdb::test {

namespace fs = std::filesystem;

/// A mesh from explicit positions and 0-based triangles.
inline TriangleMesh makeMesh(std::vector<Eigen::Vector3f> positions,
                             std::vector<TriangleMesh::Triangle> triangles) {
  TriangleMesh mesh;
  mesh.positions = std::move(positions);
  mesh.triangles = std::move(triangles);
  return mesh;
}

/// The tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1) with outward (counter-clockwise) winding.
/// Area: three right triangles of 1/2 and an equilateral one of sqrt(3)/2.
inline TriangleMesh tetrahedron() {
  return makeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                  {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
}

/// The unit cube [0,1]^3 shifted by `offset`, as 12 outward triangles over 8 vertices.
inline TriangleMesh cube(const Eigen::Vector3f& offset = Eigen::Vector3f::Zero()) {
  std::vector<Eigen::Vector3f> corners = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                          {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (Eigen::Vector3f& corner : corners) corner += offset;
  return makeMesh(corners, {{0, 3, 2},
                            {0, 2, 1},
                            {4, 5, 6},
                            {4, 6, 7},
                            {0, 1, 5},
                            {0, 5, 4},
                            {1, 2, 6},
                            {1, 6, 5},
                            {2, 3, 7},
                            {2, 7, 6},
                            {3, 0, 4},
                            {3, 4, 7}});
}

/// A closed torus (major radius 2, minor radius 0.5) sampled on a rings x segments grid, each grid
/// cell split into two triangles: V = rings*segments, E = 3V, F = 2V, Euler characteristic 0.
inline TriangleMesh torus(int rings, int segments) {
  TriangleMesh mesh;
  const double twoPi = 2.0 * std::acos(-1.0);
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      const double u = twoPi * i / rings;
      const double v = twoPi * j / segments;
      const double radius = 2.0 + 0.5 * std::cos(v);
      mesh.positions.emplace_back(static_cast<float>(radius * std::cos(u)),
                                  static_cast<float>(radius * std::sin(u)),
                                  static_cast<float>(0.5 * std::sin(v)));
    }
  }
  const auto at = [&](int i, int j) {
    return static_cast<TriangleMesh::Index>(((i % rings) * segments) + (j % segments));
  };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return mesh;
}

/// True when the two floats have identical bits (so -0 differs from +0, NaN equals itself).
inline bool sameBits(float a, float b) {
  return std::memcmp(&a, &b, sizeof(float)) == 0;
}

/// Expects identical positions (bit for bit), triangles and normals.
inline void expectIdentical(const TriangleMesh& actual, const TriangleMesh& expected) {
  ASSERT_EQ(actual.positions.size(), expected.positions.size());
  for (std::size_t v = 0; v < expected.positions.size(); ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_TRUE(sameBits(actual.positions[v][axis], expected.positions[v][axis]))
          << "vertex " << v << " axis " << axis << ": " << actual.positions[v][axis] << " vs "
          << expected.positions[v][axis];
    }
  }
  EXPECT_EQ(actual.triangles, expected.triangles);
  ASSERT_EQ(actual.normals.size(), expected.normals.size());
  for (std::size_t v = 0; v < expected.normals.size(); ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_TRUE(sameBits(actual.normals[v][axis], expected.normals[v][axis]))
          << "normal " << v << " axis " << axis;
    }
  }
}

/// Little helpers to assemble binary files in tests, independent of the library's encoder.
class ByteWriter {
 public:
  explicit ByteWriter(bool bigEndian = false) : bigEndian_(bigEndian) {}

  ByteWriter& text(const std::string& text) {
    bytes_ += text;
    return *this;
  }
  ByteWriter& u8(std::uint8_t value) { return raw(value, 1); }
  ByteWriter& i8(std::int8_t value) { return raw(static_cast<std::uint8_t>(value), 1); }
  ByteWriter& u16(std::uint16_t value) { return raw(value, 2); }
  ByteWriter& i16(std::int16_t value) { return raw(static_cast<std::uint16_t>(value), 2); }
  ByteWriter& u32(std::uint32_t value) { return raw(value, 4); }
  ByteWriter& i32(std::int32_t value) { return raw(static_cast<std::uint32_t>(value), 4); }
  ByteWriter& f32(float value) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &value, 4);
    return raw(bits, 4);
  }
  ByteWriter& f64(double value) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &value, 8);
    return raw(bits, 8);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  ByteWriter& raw(std::uint64_t value, int size) {
    for (int i = 0; i < size; ++i) {
      const int byte = bigEndian_ ? size - 1 - i : i;
      bytes_.push_back(static_cast<char>((value >> (8 * byte)) & 0xFF));
    }
    return *this;
  }

  bool bigEndian_;
  std::string bytes_;
};

}  // namespace d2vdb::test
