#include "repository/DocumentedCommands.h"

#include <cctype>
#include <regex>
#include <sstream>

namespace d2vdb::test {
namespace {

std::string withoutIndentation(const std::string& line) {
  const std::size_t start = line.find_first_not_of(" \t");
  return start == std::string::npos ? std::string() : line.substr(start);
}

// The fence a line opens or closes ("```", "````", "~~~", ...), or nothing for other lines.
std::optional<std::string> fenceOf(const std::string& line) {
  const std::string text = withoutIndentation(line);
  if (text.empty() || (text[0] != '`' && text[0] != '~')) return std::nullopt;
  const std::size_t length = text.find_first_not_of(text[0]);
  const std::size_t count = length == std::string::npos ? text.size() : length;
  if (count < 3) return std::nullopt;
  return text.substr(0, count);
}

// Whether `line` closes the code block opened by `opening`: the same character, at least as many
// times, and nothing but spaces after it.
bool closesFence(const std::string& line, const std::string& opening) {
  const std::optional<std::string> fence = fenceOf(line);
  if (!fence || (*fence)[0] != opening[0] || fence->size() < opening.size()) return false;
  const std::string rest = withoutIndentation(line).substr(fence->size());
  return rest.find_first_not_of(" \t") == std::string::npos;
}

// The text of an ATX heading ("## Title" -> "Title"), or nothing for other lines.
std::optional<std::string> headingOf(const std::string& line) {
  static const std::regex heading(R"(^#{1,6}[ \t]+(.*?)[ \t#]*$)");
  std::smatch match;
  if (!std::regex_match(line, match, heading)) return std::nullopt;
  return match[1].str();
}

bool continuesOntoNextLine(const std::string& line) {
  return !line.empty() && line.back() == '\\';
}

}  // namespace

std::optional<std::string> trailingComment(const std::string& commandLine) {
  char quote = 0;  // the quote character we are inside, or 0
  for (std::size_t i = 0; i < commandLine.size(); ++i) {
    const char c = commandLine[i];
    if (quote != 0) {
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '\\') {
      ++i;  // an escaped character, '#' included, is a literal
    } else if (c == '#' &&
               (i == 0 || std::isspace(static_cast<unsigned char>(commandLine[i - 1])))) {
      return commandLine.substr(i + 1);
    }
  }
  return std::nullopt;
}

std::optional<int> promisedExitCode(const std::string& comment) {
  static const std::regex promise(R"(\bexit code ([0-9]+)\b)");
  std::smatch match;
  if (!std::regex_search(comment, match, promise)) return std::nullopt;
  return std::stoi(match[1].str());
}

std::vector<DocumentedSection> documentedSections(const std::string& markdown) {
  std::vector<std::string> lines;
  std::istringstream in(markdown);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
  }
  std::vector<DocumentedSection> sections(1);
  std::optional<std::string> openFence;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    if (openFence) {
      if (closesFence(line, *openFence)) {
        openFence.reset();
      } else if (withoutIndentation(line).rfind("d2vdb ", 0) == 0) {
        DocumentedCommand command;
        command.line = static_cast<int>(i + 1);
        command.text = line;
        while (continuesOntoNextLine(lines[i]) && i + 1 < lines.size()) {
          command.text += "\n" + lines[++i];
        }
        const std::optional<std::string> comment = trailingComment(command.text);
        command.expectedExitCode = comment ? promisedExitCode(*comment).value_or(0) : 0;
        sections.back().commands.push_back(command);
      }
    } else if ((openFence = fenceOf(line))) {
      // The fence's info string ("sh", "json", ...) does not matter: every block is read.
    } else if (const std::optional<std::string> heading = headingOf(line)) {
      sections.push_back({*heading, static_cast<int>(i + 1), {}});
    }
  }
  std::vector<DocumentedSection> withCommands;
  for (DocumentedSection& section : sections) {
    if (!section.commands.empty()) withCommands.push_back(std::move(section));
  }
  return withCommands;
}

}  // namespace d2vdb::test
