#include "d2vdb/core/AtomicFile.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/ScratchDirectory.h"
#include "d2vdb/core/Error.h"

namespace {

namespace fs = std::filesystem;

using d2vdb::test::readWholeFile;

class AtomicFileTest : public d2vdb::test::ScratchDirectoryTest {};

TEST_F(AtomicFileTest, WritesNewFile) {
  const fs::path target = scratch_ / "a.txt";
  d2vdb::writeStreamAtomically(target, [](std::ostream& out) { out << "hello"; });
  EXPECT_EQ(readWholeFile(target), "hello");
  EXPECT_EQ(std::distance(fs::directory_iterator(scratch_), fs::directory_iterator()), 1);
}

TEST_F(AtomicFileTest, FailureLeavesExistingFileUntouchedAndNoTemporary) {
  const fs::path target = scratch_ / "a.txt";
  d2vdb::writeStreamAtomically(target, [](std::ostream& out) { out << "good"; });
  EXPECT_THROW(d2vdb::writeStreamAtomically(target,
                                            [](std::ostream& out) {
                                              out << "half-written";
                                              throw d2vdb::RuntimeFailure("boom");
                                            }),
               d2vdb::RuntimeFailure);
  EXPECT_EQ(readWholeFile(target), "good");
  EXPECT_EQ(std::distance(fs::directory_iterator(scratch_), fs::directory_iterator()), 1);
}

TEST_F(AtomicFileTest, MissingDirectoryIsAClearError) {
  const fs::path target = scratch_ / "no" / "such" / "dir" / "a.txt";
  try {
    d2vdb::writeStreamAtomically(target, [](std::ostream& out) { out << "x"; });
    FAIL() << "expected an exception";
  } catch (const d2vdb::RuntimeFailure& error) {
    EXPECT_NE(std::string(error.what()).find("does not exist"), std::string::npos) << error.what();
  }
}

TEST_F(AtomicFileTest, ReplacesExistingFile) {
  const fs::path target = scratch_ / "a.txt";
  d2vdb::writeStreamAtomically(target, [](std::ostream& out) { out << "old"; });
  d2vdb::writeStreamAtomically(target, [](std::ostream& out) { out << "new"; });
  EXPECT_EQ(readWholeFile(target), "new");
}

}  // namespace
