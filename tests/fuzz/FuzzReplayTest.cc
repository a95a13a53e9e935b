// Replays the fuzz corpora kept in the repository through the same entry points as the libFuzzer
// programs: tests/fuzz/seeds/<target>/ (valid and near-valid inputs the fuzzers start from) and
// tests/fuzz/regressions/<target>/ (every input a fuzzer found a bug with). Each must be accepted
// or rejected with InputError; a crash, another exception or a sanitizer report is a regression.
// The long fuzzing runs themselves are not part of the test suite (tools/fuzz.sh, RELIABILITY.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/FuzzEntryPoints.h"

namespace d2vdb::fuzz {
namespace {

std::vector<std::filesystem::path> corpus(const std::string& kind, const std::string& target) {
  const std::filesystem::path folder =
      std::filesystem::path(D2VDB_SOURCE_DIR) / "tests" / "fuzz" / kind / target;
  std::vector<std::filesystem::path> files;
  if (std::filesystem::is_directory(folder)) {
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
      if (entry.is_regular_file()) files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class FuzzReplayTest : public ::testing::TestWithParam<Target> {};

TEST_P(FuzzReplayTest, SeedsAndRegressionsAreAcceptedOrRejectedCleanly) {
  const Target& target = GetParam();
  const std::vector<std::filesystem::path> seeds = corpus("seeds", target.name);
  // Every target starts from seeds, and most of them must be valid inputs.
  ASSERT_FALSE(seeds.empty()) << "no seeds for " << target.name;
  int accepted = 0;
  for (const std::filesystem::path& file : seeds) {
    SCOPED_TRACE(file.string());
    const std::string input = bytes(file);
    accepted += accepts(target, reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
  }
  EXPECT_GE(accepted * 2, static_cast<int>(seeds.size())) << "most seeds should be valid inputs";
  for (const std::filesystem::path& file : corpus("regressions", target.name)) {
    SCOPED_TRACE(file.string());
    const std::string input = bytes(file);
    accepts(target, reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
  }
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzReplayTest, ::testing::ValuesIn(targets()),
                         [](const ::testing::TestParamInfo<Target>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace
}  // namespace d2vdb::fuzz
