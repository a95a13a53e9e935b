// Checking, before any work starts, that an output file can be written under the name given: its
// directory exists and is writable, and its extension names what will be written.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace d2vdb {

/// What checkOutputPath() requires of one output path.
struct OutputPathRule {
  /// How messages name the path: the option that gave it ("--mesh", "output").
  std::string label;
  /// The accepted extensions, lower case with their dot (".obj"); compared case-insensitively.
  /// Empty: any name, extension or not.
  std::vector<std::string> extensions;
  /// What is written, for the message: "a level set", "a mesh".
  std::string content;
  /// Why only these extensions, appended to the message when not empty (e.g. "--curvature adds
  /// per-vertex properties, which only PLY has").
  std::string reason;
};

/// Throws InputError naming rule.label and `path` unless a file can be written at `path`: the
/// name is not empty, is not an existing directory, its directory (the current one for a bare
/// name) exists, is a directory and is writable and searchable by this process, and its
/// extension is one of rule.extensions. Creates nothing; the file itself may exist (writers
/// replace it atomically, core/AtomicFile.h). A directory that changes after the check still
/// makes the writer fail (RuntimeFailure).
void checkOutputPath(const std::filesystem::path& path, const OutputPathRule& rule);

/// One output of checkOutputPaths(): its path ("" = not requested, skipped) and its rule.
struct OutputPathCheck {
  std::filesystem::path path;
  OutputPathRule rule;
};

/// checkOutputPath() for every requested output, then throws InputError when two of them name the
/// same file (one would overwrite the other), naming both labels.
void checkOutputPaths(const std::vector<OutputPathCheck>& outputs);

}  // namespace d2vdb
