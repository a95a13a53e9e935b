// documentedSections() on hand-written pages: which lines are commands, how continuations,
// comments, quotes and the "exit code N" marker are read, and where sections begin.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "repository/DocumentedCommands.h"

namespace {

using d2vdb::test::DocumentedSection;
using d2vdb::test::documentedSections;
using d2vdb::test::promisedExitCode;
using d2vdb::test::trailingComment;

TEST(DocumentedCommands, TakesOnlyD2vdbLinesInsideFencesAndGroupsThemByHeading) {
  const std::string page =
      "# Title\n"                                // 1
      "d2vdb info prose.vdb is not a command\n"  // 2
      "```sh\n"                                  // 3
      "# a shell comment, not a heading\n"       // 4
      "d2vdb info a.vdb\n"                       // 5
      "build/tools/d2vdb info b.vdb\n"           // 6: another program
      "  d2vdb info c.vdb\n"                     // 7: indented
      "```\n"                                    // 8
      "## Empty section\n"                       // 9
      "text\n"                                   // 10
      "### Third: `fit`\n"                       // 11
      "~~~~json\n"                               // 12
      "~~~\n"                                    // 13: shorter, does not close
      "d2vdb mesh2sdf x.obj x.vdb\n"             // 14
      "~~~~\n"                                   // 15
      "d2vdb after.vdb\n";                       // 16: outside again
  const std::vector<DocumentedSection> sections = documentedSections(page);
  ASSERT_EQ(sections.size(), 2u);
  EXPECT_EQ(sections[0].heading, "Title");
  EXPECT_EQ(sections[0].line, 1);
  ASSERT_EQ(sections[0].commands.size(), 2u);
  EXPECT_EQ(sections[0].commands[0].line, 5);
  EXPECT_EQ(sections[0].commands[0].text, "d2vdb info a.vdb");
  EXPECT_EQ(sections[0].commands[1].line, 7);
  EXPECT_EQ(sections[0].commands[1].text, "  d2vdb info c.vdb");
  EXPECT_EQ(sections[1].heading, "Third: `fit`");
  EXPECT_EQ(sections[1].line, 11);
  ASSERT_EQ(sections[1].commands.size(), 1u);
  EXPECT_EQ(sections[1].commands[0].line, 14);
}

TEST(DocumentedCommands, CommandsBeforeTheFirstHeadingFormTheirOwnSection) {
  const std::vector<DocumentedSection> sections =
      documentedSections("```\nd2vdb info a.vdb\n```\n# Next\n```\nd2vdb info b.vdb\n```\n");
  ASSERT_EQ(sections.size(), 2u);
  EXPECT_EQ(sections[0].heading, "");
  EXPECT_EQ(sections[0].line, 1);
  EXPECT_EQ(sections[1].heading, "Next");
  EXPECT_EQ(sections[1].line, 4);
}

TEST(DocumentedCommands, ContinuedLinesAreOneCommandStartingAtItsFirstLine) {
  const std::vector<DocumentedSection> sections = documentedSections(
      "## S\n```sh\nd2vdb fit-curve --target t.json \\\n    --out f.json \\\n    --json\n"
      "d2vdb info f.json\n```\n");
  ASSERT_EQ(sections.size(), 1u);
  ASSERT_EQ(sections[0].commands.size(), 2u);
  EXPECT_EQ(sections[0].commands[0].line, 3);
  EXPECT_EQ(sections[0].commands[0].text,
            "d2vdb fit-curve --target t.json \\\n    --out f.json \\\n    --json");
  EXPECT_EQ(sections[0].commands[1].line, 6);
}

TEST(DocumentedCommands, AnUnclosedFenceRunsToTheEndOfThePage) {
  const std::vector<DocumentedSection> sections =
      documentedSections("```\n# not a heading\nd2vdb info a.vdb\nd2vdb info b.vdb");
  ASSERT_EQ(sections.size(), 1u);
  EXPECT_EQ(sections[0].commands.size(), 2u);
  EXPECT_EQ(sections[0].commands[1].text, "d2vdb info b.vdb");
}

TEST(DocumentedCommands, TrailingCommentStartsAtAnUnquotedHashThatBeginsAWord) {
  EXPECT_EQ(trailingComment("d2vdb info a.vdb   # what is in it"), " what is in it");
  EXPECT_EQ(trailingComment("d2vdb info a#b.vdb"), std::nullopt);
  EXPECT_EQ(trailingComment("d2vdb info 'a #b.vdb'"), std::nullopt);
  EXPECT_EQ(trailingComment("d2vdb info \"a #b.vdb\" # c"), " c");
  EXPECT_EQ(trailingComment("d2vdb info a\\ \\#b.vdb"), std::nullopt);
  EXPECT_EQ(trailingComment("d2vdb info a.vdb \\\n  --json # last"), " last");
}

TEST(DocumentedCommands, ExitCodeMarkerIsReadFromTheTrailingCommentOnly) {
  EXPECT_EQ(promisedExitCode(" refused: exit code 2"), 2);
  EXPECT_EQ(promisedExitCode(" (exit code 3) because"), 3);
  EXPECT_EQ(promisedExitCode(" exits with 2"), std::nullopt);
  EXPECT_EQ(promisedExitCode(" exit code two"), std::nullopt);
  const std::vector<DocumentedSection> sections = documentedSections(
      "```sh\n"
      "d2vdb support bunny.vdb --out b.json   # refused: exit code 2\n"
      "d2vdb info 'exit code 2.vdb'\n"
      "d2vdb info a.vdb\n"
      "#   error: ... (exit code 2)\n"
      "```\n");
  ASSERT_EQ(sections.size(), 1u);
  ASSERT_EQ(sections[0].commands.size(), 3u);
  EXPECT_EQ(sections[0].commands[0].expectedExitCode, 2);
  EXPECT_EQ(sections[0].commands[1].expectedExitCode, 0);
  EXPECT_EQ(sections[0].commands[2].expectedExitCode, 0);
}

}  // namespace
