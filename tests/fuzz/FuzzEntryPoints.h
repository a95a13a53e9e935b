// The entry points of d2vdb's fuzz targets: each feeds one input to a reader (and to what a
// command does with its result), exactly as the libFuzzer programs (tests/fuzz/targets, built with
// -DD2VDB_FUZZ=ON) and the corpus replay test (FuzzReplayTest.cc, part of every build) do.
#pragma once

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace d2vdb::fuzz {

/// One fuzz target.
struct Target {
  const char* name;         ///< e.g. "obj"; also its folder under tests/fuzz/{seeds,regressions}
  const char* description;  ///< what it reads, for RELIABILITY.md and messages
  /// Reads the input; returns normally when it is accepted or rejected with InputError. Any
  /// other exception, crash or sanitizer report is a finding.
  void (*run)(const std::uint8_t* data, std::size_t size);
};

/// Prints the target's name (gtest parameter names).
inline void PrintTo(const Target& target, std::ostream* out) {
  *out << target.name;
}

/// Every target, in a fixed order.
const std::vector<Target>& targets();

/// The target named `name`; throws std::invalid_argument for an unknown name.
const Target& target(const std::string& name);

/// Runs `target` on the input: true when the reader accepted it, false when it rejected it with
/// InputError. Other exceptions propagate (a finding).
bool accepts(const Target& target, const std::uint8_t* data, std::size_t size);

}  // namespace d2vdb::fuzz
