#include "d2vdb/core/OutputPath.h"

#include <unistd.h>

#include <algorithm>
#include <system_error>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/core/detail/FileExtension.h"

namespace d2vdb {
namespace {

// ".obj", ".obj or .ply", ".obj, .ply or .stl".
std::string extensionList(const std::vector<std::string>& extensions) {
  std::string list;
  for (std::size_t i = 0; i < extensions.size(); ++i) {
    if (i > 0) list += i + 1 == extensions.size() ? " or " : ", ";
    list += extensions[i];
  }
  return list;
}

void checkExtension(const std::filesystem::path& path, const OutputPathRule& rule) {
  if (rule.extensions.empty()) return;
  const std::string extension = detail::lowerExtension(path);
  if (std::find(rule.extensions.begin(), rule.extensions.end(), extension) !=
      rule.extensions.end()) {
    return;
  }
  const std::string has = path.extension().empty()
                              ? std::string("has no extension")
                              : "has the extension '" + path.extension().string() + "'";
  std::string message = rule.label + " " + quotedPath(path) + " " + has + ", but " +
                        (rule.content.empty() ? std::string("the file") : rule.content) +
                        " is written there: name it with " + extensionList(rule.extensions);
  if (!rule.reason.empty()) message += " (" + rule.reason + ")";
  throw InputError(message);
}

void checkDirectory(const std::filesystem::path& path, const std::string& label) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError(label + " " + quotedPath(path) + " is a directory; name a file, e.g. " +
                     quotedPath(path / "out"));
  }
  const std::filesystem::path directory =
      path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const std::filesystem::file_status status = std::filesystem::status(directory, ec);
  if (!std::filesystem::exists(status)) {
    throw InputError(label + " " + quotedPath(path) + ": the directory " + quotedPath(directory) +
                     " does not exist; create it first");
  }
  if (!std::filesystem::is_directory(status)) {
    throw InputError(label + " " + quotedPath(path) + ": " + quotedPath(directory) +
                     " is not a directory");
  }
  if (::access(directory.c_str(), W_OK | X_OK) != 0) {
    throw InputError(label + " " + quotedPath(path) + ": the directory " + quotedPath(directory) +
                     " is not writable");
  }
}

// The file `path` names, for comparing outputs: its directory resolved (it exists), its name kept.
std::filesystem::path identity(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::path directory =
      path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  std::filesystem::path resolved = std::filesystem::weakly_canonical(directory, ec);
  if (ec) resolved = std::filesystem::absolute(directory, ec).lexically_normal();
  return resolved / path.filename();
}

}  // namespace

void checkOutputPath(const std::filesystem::path& path, const OutputPathRule& rule) {
  if (path.empty()) throw InputError(rule.label + ": no file name was given");
  if (!path.has_filename()) {
    throw InputError(rule.label + " " + quotedPath(path) + " names a directory, not a file");
  }
  checkDirectory(path, rule.label);
  checkExtension(path, rule);
}

void checkOutputPaths(const std::vector<OutputPathCheck>& outputs) {
  std::vector<std::pair<std::filesystem::path, const OutputPathCheck*>> seen;
  for (const OutputPathCheck& output : outputs) {
    if (output.path.empty()) continue;
    checkOutputPath(output.path, output.rule);
    const std::filesystem::path file = identity(output.path);
    for (const auto& [other, check] : seen) {
      if (other == file) {
        throw InputError(check->rule.label + " and " + output.rule.label + " both name " +
                         quotedPath(output.path) + "; give each output its own file");
      }
    }
    seen.emplace_back(file, &output);
  }
}

}  // namespace d2vdb
