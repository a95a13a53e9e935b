// Thread-count control for the tests that compare runs with 1 and 2 threads bit for bit.
#pragma once

#include <tbb/global_control.h>

#include <cstddef>

namespace d2vdb::test {

/// Runs `work` with TBB limited to `threads` threads and returns its result.
template <typename Work>
auto withThreads(int threads, Work&& work) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
  return work();
}

}  // namespace d2vdb::test
