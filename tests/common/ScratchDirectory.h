// A fresh scratch directory for each test, and whole-file reads and writes, shared by the test
// suites that touch files (core, mesh, io, cli).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace d2vdb::test {

/// The whole content of a file, byte for byte; empty when it does not exist.
inline std::string readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

/// Writes `contents` to `path` byte for byte (replacing the file).
inline void writeWholeFile(const std::filesystem::path& path, const std::string& contents) {
  std::ofstream out(path, std::ios::binary);
  out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
}

/// Fixture owning an empty directory under the system's temporary directory, named after the test
/// suite, the test and the process (so parallel ctest runs never share one), removed afterwards.
class ScratchDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    scratch_ = std::filesystem::temp_directory_path() /
               (std::string("d2vdb-") + info->test_suite_name() + "-" + info->name() + "-" +
                std::to_string(::getpid()));
    std::filesystem::remove_all(scratch_);
    std::filesystem::create_directories(scratch_);
  }
  void TearDown() override { std::filesystem::remove_all(scratch_); }

  /// The path of `name` inside the scratch directory.
  std::filesystem::path file(const std::string& name) const { return scratch_ / name; }

  /// Writes `contents` to `name` inside the scratch directory byte for byte; returns its path.
  std::filesystem::path write(const std::string& name, const std::string& contents) const {
    writeWholeFile(file(name), contents);
    return file(name);
  }

  std::filesystem::path scratch_;
};

}  // namespace d2vdb::test
