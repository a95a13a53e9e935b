// Writing output files so that a failure never leaves a half-written file over a good one.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>

namespace d2vdb {

/// The checks made before an atomic write of `target`: throws InputError for an empty name, and
/// RuntimeFailure when its directory does not exist or `target` is itself a directory.
void requireWritableTarget(const std::filesystem::path& target);

/// Writes `target` atomically: `write` receives the path of a temporary file in the same
/// directory (so the final rename stays on one file system), and only when it returns normally is
/// the temporary renamed over `target`. If `write` throws, the temporary is removed, `target` is
/// left exactly as it was, and the exception propagates. Throws RuntimeFailure when the temporary
/// cannot be created or renamed (e.g. the directory does not exist or is read-only).
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path& temporary)>& write);

/// Convenience form of writeFileAtomically for stream-based writers: opens the temporary as a
/// binary std::ofstream, calls `write`, flushes and checks the stream (a full disk is an error).
void writeStreamAtomically(const std::filesystem::path& target,
                           const std::function<void(std::ostream& out)>& write);

}  // namespace d2vdb
