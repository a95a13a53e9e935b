// Marching squares slices: closed circles of the right radius, orientation, offsets, SVG output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "d2vdb/contour/IsoLines.h"
#include "d2vdb/contour/IsoLinesSvg.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/field/Primitives.h"

namespace d2vdb::test {
namespace {

double signedArea(const IsoLine& line) {
  double area = 0.0;
  for (std::size_t i = 0; i < line.points.size(); ++i) {
    const auto& a = line.points[i];
    const auto& b = line.points[(i + 1) % line.points.size()];
    area += 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  return area;
}

TEST(IsoLines, SphereSlicesAreClosedCounterClockwiseCircles) {
  const Eigen::Vector3d center(0.2, -0.1, 0.3);
  const double radius = 5.0;
  PrimitiveLevelSetOptions levelSet;
  levelSet.voxelSize = 0.1;
  const auto grid = primitiveLevelSet(Sphere(center, radius), levelSet);
  for (int axis = 0; axis < 3; ++axis) {
    for (const double offset : {0.0, 1.234, -3.05}) {
      SliceOptions options;
      options.axis = axis;
      options.offset = center[axis] + offset;
      const Slice slice = sliceIsoLines(*grid, options);
      ASSERT_EQ(slice.lines.size(), 1u) << "axis " << axis << " offset " << offset;
      const IsoLine& line = slice.lines.front();
      EXPECT_TRUE(line.closed);
      const double circle = std::sqrt(radius * radius - offset * offset);
      const Eigen::Vector2d planeCenter(center[slice.planeAxes[0]], center[slice.planeAxes[1]]);
      for (const auto& point : line.points) {
        EXPECT_NEAR((point - planeCenter).norm(), circle, 0.01);
      }
      EXPECT_NEAR(signedArea(line), M_PI * circle * circle, 0.01 * M_PI * circle * circle);
    }
  }
}

TEST(IsoLines, TorusSliceHasTwoLoopsAndSvgIsWritten) {
  PrimitiveLevelSetOptions levelSet;
  levelSet.voxelSize = 0.05;
  const auto grid = primitiveLevelSet(Torus(Eigen::Vector3d::Zero(), 2.0, 0.5), levelSet);
  SliceOptions options;
  options.offset = 0.1;
  const Slice slice = sliceIsoLines(*grid, options);
  ASSERT_EQ(slice.lines.size(), 2u);
  double total = 0.0;
  for (const IsoLine& line : slice.lines) {
    EXPECT_TRUE(line.closed);
    total += signedArea(line);
  }
  // The annulus: outer circle counter-clockwise, inner one clockwise (inside on the left).
  const double half = std::sqrt(0.25 - 0.01);
  EXPECT_NEAR(total, M_PI * (std::pow(2.0 + half, 2) - std::pow(2.0 - half, 2)), 0.02);

  const auto path = std::filesystem::temp_directory_path() /
                    ("d2vdb-isolines-" + std::to_string(::getpid()) + ".svg");
  writeIsoLinesSvg(path, slice);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::filesystem::remove(path);
  EXPECT_NE(text.str().find("<svg"), std::string::npos);
  // Both loops are closed: one <polygon> each, no open <polyline>.
  std::size_t polygons = 0;
  for (std::size_t at = text.str().find("<polygon"); at != std::string::npos;
       at = text.str().find("<polygon", at + 1)) {
    ++polygons;
  }
  EXPECT_EQ(polygons, 2u);
  EXPECT_EQ(text.str().find("<polyline"), std::string::npos);
}

TEST(IsoLines, RejectsBadParameters) {
  const auto grid = openvdb::FloatGrid::create(1.0f);
  SliceOptions options;
  options.axis = 3;
  EXPECT_THROW(sliceIsoLines(*grid, options), InputError);
  options.axis = 0;
  options.offset = std::nan("");
  EXPECT_THROW(sliceIsoLines(*grid, options), InputError);
  options.offset = 0.0;
  EXPECT_TRUE(sliceIsoLines(*grid, options).lines.empty());
}

}  // namespace
}  // namespace d2vdb::test
