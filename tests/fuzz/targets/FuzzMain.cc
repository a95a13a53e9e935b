// The libFuzzer program of one target (D2VDB_FUZZ_TARGET, e.g. "obj"), built with -DD2VDB_FUZZ=ON
// under clang as fuzz_<target>; run it with tools/fuzz.sh. Inputs rejected with InputError are
// fine; any other exception aborts, which libFuzzer reports as a crash with the input.
#include <cstddef>
#include <cstdint>

#include "fuzz/FuzzEntryPoints.h"

#ifndef D2VDB_FUZZ_TARGET
#error "compile with -DD2VDB_FUZZ_TARGET=\"<name>\""
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const d2vdb::fuzz::Target& target = d2vdb::fuzz::target(D2VDB_FUZZ_TARGET);
  d2vdb::fuzz::accepts(target, data, size);
  return 0;
}
