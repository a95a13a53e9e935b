// formatNumber() and formatPoint() against what a std::ostream prints at the same precision (the
// way messages were formatted before both existed), and the shortest round-trip text.
#include "d2vdb/core/NumberFormat.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace d2vdb {
namespace {

std::string streamed(const Eigen::Vector3d& point, int precision) {
  std::ostringstream out;
  out.precision(precision);
  out << "(" << point.x() << ", " << point.y() << ", " << point.z() << ")";
  return out.str();
}

std::vector<double> sampleValues() {
  std::vector<double> values = {0.0,      -0.0,      1.0,      -1.0,  0.1,     1.0 / 3.0, 2.5e-7,
                                123456.0, 1234567.0, 99999.95, 1e300, -1e-300, 0.5,       100.0};
  std::mt19937_64 random(42);
  for (int i = 0; i < 2000; ++i) {
    // Random bit patterns of finite doubles: every exponent, every mantissa.
    std::uint64_t bits = random();
    double value = 0.0;
    std::memcpy(&value, &bits, sizeof value);
    if (std::isfinite(value)) values.push_back(value);
  }
  return values;
}

TEST(NumberFormat, PointMatchesAStreamAtTheSamePrecision) {
  const std::vector<double> values = sampleValues();
  for (const int precision : {6, 9, 15, 17}) {
    for (std::size_t i = 0; i + 2 < values.size(); ++i) {
      const Eigen::Vector3d point(values[i], values[i + 1], values[i + 2]);
      ASSERT_EQ(formatPoint(point, precision), streamed(point, precision)) << precision;
    }
  }
}

TEST(NumberFormat, TwoDimensionalPointsOmitZ) {
  EXPECT_EQ(formatPoint(Eigen::Vector3d(1.5, -2, 7), 6, 2), "(1.5, -2)");
  EXPECT_EQ(formatPoint(Eigen::Vector3d(1.5, -2, 7), 6), "(1.5, -2, 7)");
}

TEST(NumberFormat, ShortestTextReadsBackExactly) {
  EXPECT_EQ(formatNumber(0.1), "0.1");
  EXPECT_EQ(formatNumber(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(formatNumber(1e-300), "1e-300");
  for (const double value : sampleValues()) {
    ASSERT_EQ(std::strtod(formatNumber(value).c_str(), nullptr), value) << formatNumber(value);
  }
  EXPECT_EQ(formatNumber(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(formatNumber(-std::numeric_limits<double>::infinity()), "-inf");
}

}  // namespace
}  // namespace d2vdb
