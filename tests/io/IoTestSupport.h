// Shared helpers of the file-format tests: bitwise comparison, expected-error checks and a fixture
// with a fresh temporary directory per test.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb::test {

/// True when the two doubles have identical bits (an exact round trip).
inline bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof(double)) == 0;
}

/// Expects `call` to throw InputError whose message contains every one of `texts`.
template <typename Call>
void expectInputError(Call&& call, std::initializer_list<std::string> texts) {
  try {
    call();
    ADD_FAILURE() << "expected InputError containing '" << *texts.begin() << "'";
  } catch (const InputError& error) {
    for (const std::string& text : texts) {
      EXPECT_NE(std::string(error.what()).find(text), std::string::npos)
          << "'" << text << "' not in: " << error.what();
    }
  }
}

/// A fixture owning an empty temporary directory named after the test (removed afterwards).
class TemporaryDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 (std::string("d2vdb-io-") +
                  ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() + "-" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name() + "-" +
                  std::to_string(::getpid()));
    std::filesystem::remove_all(directory_);
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  /// Path of `name` inside the directory.
  std::filesystem::path file(const std::string& name) const { return directory_ / name; }

  /// Writes `text` verbatim to `name` and returns its path.
  std::filesystem::path writeText(const std::string& name, const std::string& text) const {
    std::ofstream out(file(name), std::ios::binary);
    out << text;
    return file(name);
  }

  std::filesystem::path directory_;
};

}  // namespace d2vdb::test
