// Writing several files as one: each is written to a temporary name beside its target, and the
// targets are replaced only once every file has been written, so a failure in any of them leaves
// all existing files as they were.
#pragma once

#include <filesystem>
#include <functional>
#include <utility>
#include <vector>

namespace d2vdb {

/// A transaction over output files. stage() writes one file under a temporary name in the target's
/// directory (same extension, so writers that choose the format by extension still work);
/// commit() renames every staged file onto its target. Destroying the set without commit(), or a
/// stage() that throws, removes the temporaries and leaves every target untouched.
///
/// Renames are atomic one by one, not as a set: commit() renames in staging order, and if one
/// rename fails (a directory removed meanwhile) the files renamed before it stay replaced, the
/// others keep their old content, and RuntimeFailure names the file. Not thread-safe.
class AtomicFileSet {
 public:
  AtomicFileSet() = default;
  ~AtomicFileSet();
  AtomicFileSet(const AtomicFileSet&) = delete;
  AtomicFileSet& operator=(const AtomicFileSet&) = delete;

  /// Calls write(temporary) with a fresh temporary path beside `target` (e.g. "out.d2vdb-set-
  /// 123-4.obj" for "out.obj"); the file it writes there becomes `target` at commit(). Throws
  /// InputError for an empty name or a target staged twice, RuntimeFailure when the directory
  /// does not exist or the target is a directory; whatever `write` throws propagates after its
  /// temporary is removed (the files staged before stay staged).
  void stage(const std::filesystem::path& target,
             const std::function<void(const std::filesystem::path& temporary)>& write);

  /// Renames every staged file onto its target, in staging order; afterwards the set is empty.
  /// RuntimeFailure when a rename fails (see the class comment).
  void commit();

  /// Number of files staged and not yet committed.
  std::size_t size() const { return staged_.size(); }

 private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_;  // target, temp
};

}  // namespace d2vdb
