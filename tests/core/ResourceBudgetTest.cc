// The memory and output budget: byte counts as the options read them, the messages of a refusal,
// and the bisection that finds the value that would fit (against a linear scan).
#include "d2vdb/core/ResourceBudget.h"

#include <gtest/gtest.h>

#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

TEST(ResourceBudget, ParsesByteCountsWithDecimalAndBinaryUnits) {
  EXPECT_EQ(parseByteSize("0", "--max-memory"), 0u);
  EXPECT_EQ(parseByteSize("1234", "--max-memory"), 1234u);
  EXPECT_EQ(parseByteSize("1e9", "--max-memory"), 1000000000u);
  EXPECT_EQ(parseByteSize("512B", "--max-memory"), 512u);
  EXPECT_EQ(parseByteSize("2k", "--max-memory"), 2000u);
  EXPECT_EQ(parseByteSize("1.5M", "--max-memory"), 1500000u);
  EXPECT_EQ(parseByteSize("16G", "--max-memory"), 16000000000u);
  EXPECT_EQ(parseByteSize("16gb", "--max-memory"), 16000000000u);
  EXPECT_EQ(parseByteSize("3T", "--max-memory"), 3000000000000u);
  EXPECT_EQ(parseByteSize("1KiB", "--max-memory"), 1024u);
  EXPECT_EQ(parseByteSize("512MiB", "--max-memory"), 512u << 20);
  EXPECT_EQ(parseByteSize("16GiB", "--max-memory"), std::uint64_t{16} << 30);
  EXPECT_EQ(parseByteSize("16gib", "--max-memory"), std::uint64_t{16} << 30);
  for (const char* bad : {"", "G", "-1", "12Q", "1GG", "nan", "inf", "1e30", "12 G", "1Mi"}) {
    try {
      parseByteSize(bad, "--max-output");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("--max-output"), std::string::npos) << bad;
    }
  }
}

TEST(ResourceBudget, FormatsByteCountsWithThreeDigits) {
  EXPECT_EQ(byteSizeText(0), "0 B");
  EXPECT_EQ(byteSizeText(512), "512 B");
  EXPECT_EQ(byteSizeText(41234), "41.2 kB");
  EXPECT_EQ(byteSizeText(1.19e9), "1.19 GB");
  EXPECT_EQ(byteSizeText(17179869184.0), "17.2 GB");
  EXPECT_EQ(byteSizeText(1e40), "inf");
}

TEST(ResourceBudget, RefusesAboveTheLimitNamingTheOptionAndTheRemedy) {
  ResourceBudget budget;
  budget.maxMemoryBytes = 1000;
  budget.maxOutputBytes = 2000;
  EXPECT_NO_THROW(enforceMemoryBudget({"x", 1000.0, ""}, budget));
  EXPECT_NO_THROW(enforceOutputBudget({"x", 2000.0, ""}, budget));
  try {
    enforceMemoryBudget({"fitting 3 x 3 control points", 1001.0, "use --sensors 2 or fewer"},
                        budget);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "fitting 3 x 3 control points would need about 1 kB of memory, above the memory "
              "budget of 1 kB (--max-memory); use --sensors 2 or fewer, or raise --max-memory");
  }
  try {
    enforceOutputBudget({"a mesh", 5e9, ""}, budget);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "a mesh would need about 5 GB of output files, above the output budget of 2 kB "
              "(--max-output); raise --max-output");
  }
  // A limit of zero never refuses.
  budget.maxMemoryBytes = budget.maxOutputBytes = 0;
  EXPECT_NO_THROW(enforceMemoryBudget({"x", 1e300, ""}, budget));
  EXPECT_NO_THROW(enforceOutputBudget({"x", 1e300, ""}, budget));
}

TEST(ResourceBudget, LargestFittingAgreesWithALinearScan) {
  for (long long threshold = -3; threshold <= 40; ++threshold) {
    const auto fits = [threshold](long long n) { return n <= threshold; };
    long long expected = -1;  // low - 1 with low = 0
    for (long long n = 0; n <= 30; ++n) {
      if (fits(n)) expected = n;
    }
    EXPECT_EQ(largestFitting(0, 30, fits), expected) << threshold;
  }
  EXPECT_EQ(largestFitting(5, 4, [](long long) { return true; }), 4);
}

}  // namespace
}  // namespace d2vdb
