#include "d2vdb/core/AtomicFile.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "d2vdb/core/Error.h"

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ =
        fs::temp_directory_path() /
        ("d2vdb-atomic-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "-" +
         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }
  fs::path directory_;
};

TEST_F(AtomicFileTest, WritesNewFile) {
  const fs::path target = directory_ / "a.txt";
  d2vdb::writeStreamAtomically(target, [](std::ostream& out) { out << "hello"; });
  EXPECT_EQ(slurp(target), "hello");
  EXPECT_EQ(std::distance(fs::directory_iterator(directory_), fs::directory_iterator()), 1);
}

TEST_F(AtomicFileTest, FailureLeavesExistingFileUntouchedAndNoTemporary) {
  const fs::path target = directory_ / "a.txt";
  d2vdb::writeStreamAtomically(target, [](std::ostream& out) { out << "good"; });
  EXPECT_THROW(d2vdb::writeStreamAtomically(target,
                                            [](std::ostream& out) {
                                              out << "half-written";
                                              throw d2vdb::RuntimeFailure("boom");
                                            }),
               d2vdb::RuntimeFailure);
  EXPECT_EQ(slurp(target), "good");
  EXPECT_EQ(std::distance(fs::directory_iterator(directory_), fs::directory_iterator()), 1);
}

TEST_F(AtomicFileTest, MissingDirectoryIsAClearError) {
  const fs::path target = directory_ / "no" / "such" / "dir" / "a.txt";
  try {
    d2vdb::writeStreamAtomically(target, [](std::ostream& out) { out << "x"; });
    FAIL() << "expected an exception";
  } catch (const d2vdb::RuntimeFailure& error) {
    EXPECT_NE(std::string(error.what()).find("does not exist"), std::string::npos) << error.what();
  }
}

TEST_F(AtomicFileTest, ReplacesExistingFile) {
  const fs::path target = directory_ / "a.txt";
  d2vdb::writeStreamAtomically(target, [](std::ostream& out) { out << "old"; });
  d2vdb::writeStreamAtomically(target, [](std::ostream& out) { out << "new"; });
  EXPECT_EQ(slurp(target), "new");
}

}  // namespace
