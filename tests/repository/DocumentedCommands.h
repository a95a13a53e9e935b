// The d2vdb command lines of a Markdown page's fenced code blocks, grouped by the heading they
// stand under: what ReadmeExamplesTest runs, exactly as a reader would type them.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace d2vdb::test {

/// One command of a fenced code block: a line whose text (after any indentation) begins with
/// "d2vdb ", joined with the lines it continues onto (a line ending in a backslash continues).
struct DocumentedCommand {
  int line = 0;      ///< 1-based line of the page where the command starts
  std::string text;  ///< the command as written, continuations kept as backslash-newline
  /// The exit code the command must return: 0, or N when its trailing shell comment says
  /// "exit code N" (a line that is meant to fail, e.g. `d2vdb ... # refused: exit code 2`).
  int expectedExitCode = 0;
};

/// The commands under one heading, in page order. They are meant to run one after the other in
/// one directory, each free to use the files the earlier ones wrote.
struct DocumentedSection {
  std::string heading;  ///< the heading's text without its '#'s; empty before the first heading
  int line = 1;         ///< the heading's line (1 before the first heading)
  std::vector<DocumentedCommand> commands;
};

/// The sections of a Markdown page that hold at least one command, in page order. Headings are
/// ATX headings ("# ", "## ", ...) outside code blocks; a fence is a line of three or more
/// backticks or tildes, closed by a line of at least as many of the same character (an unclosed
/// fence runs to the end of the page). Commands outside fences are prose, not commands.
std::vector<DocumentedSection> documentedSections(const std::string& markdown);

/// The comment that ends a shell command line: the text after the first '#' that starts a word
/// outside single or double quotes (without the '#'); nothing when there is none.
std::optional<std::string> trailingComment(const std::string& commandLine);

/// The exit code a comment promises ("... exit code N ..."), or nothing when it names none.
std::optional<int> promisedExitCode(const std::string& comment);

}  // namespace d2vdb::test
