// Every d2vdb command line of the documentation runs as written: README.md and, when the folder
// exists, every docs/**/*.md (in path order). documentedSections() (DocumentedCommands.h) finds the
// lines that begin with "d2vdb " in fenced code blocks; the lines under one heading run in order,
// each by /bin/sh exactly as written, in a fresh directory holding a copy of volumes/, with the
// built d2vdb first on PATH, so a line may use the bundled files (volumes/...) and the files that
// the lines before it under the same heading wrote, and nothing else.
//
// A line passes when it exits with 0. A line meant to fail says so in its trailing comment:
// "exit code N" there (e.g. `d2vdb support volumes/bunny.vdb --out b.json   # refused: exit
// code 2`) makes N, and only N, a pass. On a failure the test names the page, the line, the
// command and its stderr, and skips the rest of that section (later lines may need its output).
//
// Keep the examples small: the whole run takes seconds in a Release build and runs under the
// sanitizers too. Each command's time is printed.
//
// The examples of every sub-command's --help ("Example: d2vdb ..." and the "d2vdb ..." lines
// below it) run the same way, all in one directory holding a copy of volumes/: an example may
// use what another sub-command's example writes (the query examples read the field example's
// output), so a failing one is run once more after all the others.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "common/ScratchDirectory.h"
#include "repository/DocumentedCommands.h"

namespace {

namespace fs = std::filesystem;
using d2vdb::test::DocumentedCommand;
using d2vdb::test::DocumentedSection;
using d2vdb::test::readWholeFile;

// The pages whose examples are run, relative to the source tree.
std::vector<std::string> documentationPages() {
  std::vector<std::string> pages = {"README.md"};
  const fs::path docs = fs::path(D2VDB_SOURCE_DIR) / "docs";
  if (fs::is_directory(docs)) {
    std::vector<std::string> found;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(docs)) {
      if (entry.is_regular_file() && entry.path().extension() == ".md") {
        found.push_back(fs::relative(entry.path(), D2VDB_SOURCE_DIR).generic_string());
      }
    }
    std::sort(found.begin(), found.end());
    pages.insert(pages.end(), found.begin(), found.end());
  }
  return pages;
}

std::string quotedForShell(const fs::path& path) {
  std::string quoted = "'";
  for (const char c : path.string()) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

struct CommandRun {
  int exitCode = -1;
  std::string err;
  double seconds = 0;
};

// Runs `command` with /bin/sh in `directory` with `bin` first on PATH, stdin empty, stdout and
// stderr captured in files beside the directory.
CommandRun runInDirectory(const DocumentedCommand& command, const fs::path& directory,
                          const fs::path& bin) {
  const fs::path outPath = directory.parent_path() / (directory.filename().string() + ".stdout");
  const fs::path errPath = directory.parent_path() / (directory.filename().string() + ".stderr");
  const std::string shell = "cd " + quotedForShell(directory) + " && PATH=" + quotedForShell(bin) +
                            ":\"$PATH\" && {\n" + command.text + "\n} >" + quotedForShell(outPath) +
                            " 2>" + quotedForShell(errPath) + " </dev/null";
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(shell.c_str());
  CommandRun run;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.err = readWholeFile(errPath);
  return run;
}

class ReadmeExamplesTest : public d2vdb::test::ScratchDirectoryTest {
 protected:
  void SetUp() override {
    ScratchDirectoryTest::SetUp();
    bin_ = scratch_ / "bin";
    fs::create_directories(bin_);
    fs::create_symlink(fs::absolute(D2VDB_CLI), bin_ / "d2vdb");
  }

  // Runs one section's commands in order in a fresh directory; returns the number that ran.
  int runSection(const std::string& page, const DocumentedSection& section, int index) {
    const fs::path directory = scratch_ / ("section-" + std::to_string(index));
    fs::create_directories(directory);
    fs::copy(fs::path(D2VDB_SOURCE_DIR) / "volumes", directory / "volumes",
             fs::copy_options::recursive);
    int ran = 0;
    for (std::size_t k = 0; k < section.commands.size(); ++k) {
      const DocumentedCommand& command = section.commands[k];
      const CommandRun run = runInDirectory(command, directory, bin_);
      ++ran;
      std::cout << page << ":" << command.line << "  " << std::fixed << std::setprecision(2)
                << run.seconds << " s  exit " << run.exitCode << "\n";
      totalSeconds_ += run.seconds;
      if (run.exitCode != command.expectedExitCode) {
        ADD_FAILURE() << page << ":" << command.line << " (under \"" << section.heading
                      << "\"):\n  " << command.text << "\nexited with " << run.exitCode
                      << ", expected " << command.expectedExitCode
                      << (command.expectedExitCode == 0
                              ? ""
                              : " (its comment says \"exit code " +
                                    std::to_string(command.expectedExitCode) + "\")")
                      << "; stderr:\n"
                      << run.err << "\n(" << section.commands.size() - k - 1
                      << " later lines of this section not run)";
        break;
      }
    }
    return ran;
  }

  fs::path bin_;
  double totalSeconds_ = 0;
};

TEST_F(ReadmeExamplesTest, EveryCommandLineRunsAsWritten) {
  int pageIndex = 0, sectionIndex = 0, commands = 0;
  for (const std::string& page : documentationPages()) {
    const std::string text = readWholeFile(fs::path(D2VDB_SOURCE_DIR) / page);
    ASSERT_FALSE(text.empty()) << "cannot read " << page;
    const std::vector<DocumentedSection> sections = d2vdb::test::documentedSections(text);
    if (pageIndex++ == 0) {
      ASSERT_FALSE(sections.empty()) << page << " has no d2vdb command in a code block";
    }
    for (const DocumentedSection& section : sections) {
      commands += runSection(page, section, sectionIndex++);
    }
  }
  std::cout << commands << " commands in " << sectionIndex << " sections, " << std::fixed
            << std::setprecision(1) << totalSeconds_ << " s\n";
}

// The sub-command names the top-level --help lists, in its order.
std::vector<std::string> subcommandNames(const std::string& help) {
  std::vector<std::string> names;
  std::istringstream lines(help.substr(std::min(help.find("Subcommands:"), help.size())));
  const std::regex name(R"(^  ([a-z0-9][a-z0-9-]*)  )");
  std::string line;
  std::smatch match;
  while (std::getline(lines, line)) {
    if (std::regex_search(line, match, name)) names.push_back(match[1]);
  }
  return names;
}

// The example lines of one sub-command's --help: the text after "Example: " and the lines that
// continue it, each a command starting with "d2vdb ".
std::vector<std::string> helpExamples(const std::string& help) {
  std::vector<std::string> examples;
  std::istringstream lines(help);
  std::string line;
  bool inExamples = false;
  while (std::getline(lines, line)) {
    const std::size_t example = line.find("Example: d2vdb ");
    const std::size_t first = line.find_first_not_of(' ');
    if (example != std::string::npos) {
      examples.push_back(line.substr(example + 9));
      inExamples = true;
    } else if (inExamples && first != std::string::npos && line.compare(first, 6, "d2vdb ") == 0) {
      examples.push_back(line.substr(first));
    } else {
      inExamples = false;
    }
  }
  return examples;
}

TEST_F(ReadmeExamplesTest, EveryHelpExampleRuns) {
  const fs::path directory = scratch_ / "help-examples";
  fs::create_directories(directory);
  fs::copy(fs::path(D2VDB_SOURCE_DIR) / "volumes", directory / "volumes",
           fs::copy_options::recursive);
  const auto helpOf = [&](const std::string& arguments) {
    const CommandRun run = runInDirectory({0, "d2vdb " + arguments, 0}, directory, bin_);
    EXPECT_EQ(run.exitCode, 0) << "d2vdb " << arguments << ": " << run.err;
    return readWholeFile(directory.parent_path() / "help-examples.stdout");
  };
  const std::vector<std::string> names = subcommandNames(helpOf("--help"));
  ASSERT_GE(names.size(), 15u);
  std::vector<std::pair<std::string, std::string>> examples;  // sub-command, command line
  for (const std::string& name : names) {
    const std::vector<std::string> lines = helpExamples(helpOf(name + " --help"));
    EXPECT_FALSE(lines.empty()) << "'d2vdb " << name << " --help' shows no example";
    for (const std::string& line : lines) examples.emplace_back(name, line);
  }
  std::vector<std::pair<std::string, std::string>> failed;
  for (const auto& [name, line] : examples) {
    if (runInDirectory({0, line, 0}, directory, bin_).exitCode != 0)
      failed.emplace_back(name, line);
  }
  for (const auto& [name, line] : failed) {
    const CommandRun run = runInDirectory({0, line, 0}, directory, bin_);
    EXPECT_EQ(run.exitCode, 0) << "the example of 'd2vdb " << name << " --help':\n  " << line
                               << "\nexited with " << run.exitCode << "; stderr:\n"
                               << run.err;
  }
  std::cout << examples.size() << " --help examples of " << names.size() << " sub-commands\n";
}

}  // namespace
