// Several files written as one: nothing is replaced unless every file was written.
#include "d2vdb/core/AtomicFileSet.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/ScratchDirectory.h"
#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/Error.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::readWholeFile;
using d2vdb::test::writeWholeFile;

class AtomicFileSetTest : public d2vdb::test::ScratchDirectoryTest {
 protected:
  std::size_t fileCount() const {
    return static_cast<std::size_t>(
        std::distance(fs::directory_iterator(scratch_), fs::directory_iterator()));
  }
  static void writeText(const fs::path& path, const std::string& text) {
    d2vdb::writeStreamAtomically(path, [&](std::ostream& out) { out << text; });
  }
};

TEST_F(AtomicFileSetTest, CommitReplacesEveryFile) {
  writeWholeFile(file("a.json"), "old a");
  writeWholeFile(file("b.obj"), "old b");
  d2vdb::AtomicFileSet files;
  files.stage(file("a.json"), [](const fs::path& temporary) { writeText(temporary, "new a"); });
  const fs::path directory = file("b.obj").parent_path();
  files.stage(file("b.obj"), [&directory](const fs::path& temporary) {
    // Writers that choose the format by extension see the target's extension.
    EXPECT_EQ(temporary.extension(), ".obj");
    EXPECT_EQ(temporary.parent_path(), directory);
    writeText(temporary, "new b");
  });
  files.stage(file("c.svg"), [](const fs::path& temporary) { writeText(temporary, "new c"); });
  EXPECT_EQ(files.size(), 3u);
  // Nothing is replaced before the commit.
  EXPECT_EQ(readWholeFile(file("a.json")), "old a");
  EXPECT_FALSE(fs::exists(file("c.svg")));
  files.commit();
  EXPECT_EQ(files.size(), 0u);
  EXPECT_EQ(readWholeFile(file("a.json")), "new a");
  EXPECT_EQ(readWholeFile(file("b.obj")), "new b");
  EXPECT_EQ(readWholeFile(file("c.svg")), "new c");
  EXPECT_EQ(fileCount(), 3u);  // no temporaries left
}

TEST_F(AtomicFileSetTest, AFailureInTheSecondFileLeavesTheFirstFilesOldContent) {
  writeWholeFile(file("first.json"), "old first");
  writeWholeFile(file("second.ply"), "old second");
  {
    d2vdb::AtomicFileSet files;
    files.stage(file("first.json"),
                [](const fs::path& temporary) { writeText(temporary, "new first"); });
    EXPECT_THROW(files.stage(file("second.ply"),
                             [](const fs::path& temporary) {
                               std::ofstream(temporary) << "half-written";
                               throw d2vdb::RuntimeFailure("disk full");
                             }),
                 d2vdb::RuntimeFailure);
    // The caller's exception leaves the set uncommitted: its destructor removes the staged file.
  }
  EXPECT_EQ(readWholeFile(file("first.json")), "old first");
  EXPECT_EQ(readWholeFile(file("second.ply")), "old second");
  EXPECT_EQ(fileCount(), 2u);
}

TEST_F(AtomicFileSetTest, RefusesBadTargetsBeforeWriting) {
  d2vdb::AtomicFileSet files;
  bool called = false;
  const auto write = [&called](const fs::path& temporary) {
    called = true;
    writeText(temporary, "x");
  };
  EXPECT_THROW(files.stage("", write), d2vdb::InputError);
  EXPECT_THROW(files.stage(file("missing/a.obj"), write), d2vdb::RuntimeFailure);
  EXPECT_THROW(files.stage(scratch_, write), d2vdb::RuntimeFailure);
  EXPECT_FALSE(called);
  files.stage(file("a.obj"), write);
  EXPECT_THROW(files.stage(file("a.obj"), write), d2vdb::InputError);
  EXPECT_EQ(files.size(), 1u);
}

}  // namespace
