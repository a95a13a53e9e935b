// The memory and output-size budget every operation checks its own estimate against before it
// allocates or writes anything, so that an absurd option on a small input is refused with a
// message naming the option, instead of running for minutes and failing for want of memory.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace d2vdb {

/// Default memory budget in bytes: 16 GiB, two thirds of the 24 GiB machines d2vdb is measured
/// on (the rest for the system, the page cache and a second process).
inline constexpr std::uint64_t kDefaultMaxMemoryBytes = std::uint64_t{16} << 30;

/// Default output budget in bytes: 512 MiB written by one operation, all its files together.
/// Ten times the approximant field of the dragon at resolution 512 (99.6 MB, BENCHMARKS.md); an
/// output larger than this from a small input is almost always a mistyped option.
inline constexpr std::uint64_t kDefaultMaxOutputBytes = std::uint64_t{512} << 20;

/// The limits one operation's estimates are checked against. Both in bytes; 0 means no limit.
struct ResourceBudget {
  std::uint64_t maxMemoryBytes = kDefaultMaxMemoryBytes;  ///< peak memory of the work
  std::uint64_t maxOutputBytes = kDefaultMaxOutputBytes;  ///< bytes of all files written
};

/// What enforceMemoryBudget() and enforceOutputBudget() say when an estimate is too large.
struct BudgetRequest {
  /// What is estimated, e.g. "fitting 100 x 100 control points with 100^2 sensors per knot cell".
  std::string subject;
  /// The estimate in bytes (a double: absurd requests exceed 2^64).
  double estimatedBytes = 0.0;
  /// What to change, naming the option and the value that fits, e.g. "use --sensors 12 or
  /// fewer". Empty: no advice beyond raising the budget.
  std::string remedy;
};

/// Throws InputError when request.estimatedBytes exceeds budget.maxMemoryBytes (a limit of 0
/// never refuses): "<subject> would need about 28.1 GB of memory, above the memory budget of
/// 17.2 GB (--max-memory); <remedy>, or raise --max-memory". Allocates nothing itself.
void enforceMemoryBudget(const BudgetRequest& request, const ResourceBudget& budget);

/// As enforceMemoryBudget() for the bytes written (budget.maxOutputBytes, --max-output).
void enforceOutputBudget(const BudgetRequest& request, const ResourceBudget& budget);

/// A byte count for messages, in decimal units with three significant digits: "512 B", "41.2 kB",
/// "1.19 GB"; "inf" for an infinite or non-representable count.
std::string byteSizeText(double bytes);

/// Reads a byte count as the options --max-memory and --max-output take it: a non-negative number
/// with an optional unit, B, k/K, M, G, T (powers of 1000) or KiB, MiB, GiB, TiB (powers of 1024),
/// any letter case ("16G", "512MiB", "1e9"); 0 means no limit. Throws InputError naming `option`
/// for anything else or a value beyond 2^64 bytes.
std::uint64_t parseByteSize(const std::string& text, const std::string& option);

/// The largest integer n in [low, high] for which `fits(n)` holds, assuming `fits` is monotone
/// (true up to some n, false above), by bisection; low - 1 when even `low` does not fit. For the
/// "the value that would fit" part of the messages.
long long largestFitting(long long low, long long high, const std::function<bool(long long)>& fits);

}  // namespace d2vdb
