#include "d2vdb/core/AtomicFile.h"

#include <unistd.h>

#include <atomic>
#include <string>
#include <system_error>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

std::filesystem::path temporaryBeside(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path temporary = target;
  temporary += ".d2vdb-tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  return temporary;
}

}  // namespace

void requireWritableTarget(const std::filesystem::path& target) {
  if (target.empty()) throw InputError("no output file name was given");
  const std::filesystem::path directory =
      target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(directory, ec)) {
    throw RuntimeFailure("cannot write '" + target.string() + "': directory '" +
                         directory.string() + "' does not exist");
  }
  if (std::filesystem::is_directory(target, ec)) {
    throw RuntimeFailure("cannot write '" + target.string() + "': it is a directory");
  }
}

void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path&)>& write) {
  requireWritableTarget(target);
  std::error_code ec;
  const std::filesystem::path temporary = temporaryBeside(target);
  try {
    write(temporary);
  } catch (...) {
    std::filesystem::remove(temporary, ec);
    throw;
  }
  std::filesystem::rename(temporary, target, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw RuntimeFailure("cannot write '" + target.string() + "': " + ec.message());
  }
}

void writeStreamAtomically(const std::filesystem::path& target,
                           const std::function<void(std::ostream&)>& write) {
  writeFileAtomically(target, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw RuntimeFailure("cannot create '" + temporary.string() +
                           "' (is the directory writable?)");
    }
    write(out);
    out.flush();
    if (!out) throw RuntimeFailure("write error on '" + target.string() + "' (disk full?)");
  });
}

}  // namespace d2vdb
