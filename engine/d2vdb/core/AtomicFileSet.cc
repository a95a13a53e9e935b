#include "d2vdb/core/AtomicFileSet.h"

#include <unistd.h>

#include <atomic>
#include <string>
#include <system_error>

#include "d2vdb/core/AtomicFile.h"
#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

std::filesystem::path temporaryFor(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path temporary = target;
  temporary.replace_filename(target.stem().string() + ".d2vdb-set-" + std::to_string(::getpid()) +
                             "-" + std::to_string(counter++) + target.extension().string());
  return temporary;
}

}  // namespace

AtomicFileSet::~AtomicFileSet() {
  std::error_code ignored;
  for (const auto& file : staged_) std::filesystem::remove(file.second, ignored);
}

void AtomicFileSet::stage(const std::filesystem::path& target,
                          const std::function<void(const std::filesystem::path&)>& write) {
  requireWritableTarget(target);
  for (const auto& file : staged_) {
    if (std::filesystem::absolute(file.first) == std::filesystem::absolute(target)) {
      throw InputError("the output '" + target.string() + "' is written twice");
    }
  }
  std::error_code ec;
  const std::filesystem::path temporary = temporaryFor(target);
  try {
    write(temporary);
  } catch (...) {
    std::filesystem::remove(temporary, ec);
    throw;
  }
  staged_.emplace_back(target, temporary);
}

void AtomicFileSet::commit() {
  for (std::size_t i = 0; i < staged_.size(); ++i) {
    std::error_code ec;
    std::filesystem::rename(staged_[i].second, staged_[i].first, ec);
    if (ec) {
      const std::string target = staged_[i].first.string();
      staged_.erase(staged_.begin(), staged_.begin() + static_cast<std::ptrdiff_t>(i));
      throw RuntimeFailure("cannot write '" + target + "': " + ec.message() +
                           (i > 0 ? " (the outputs before it were written)" : ""));
    }
  }
  staged_.clear();
}

}  // namespace d2vdb
