// Shared helpers of the file-format tests: bitwise comparison, plus the expected-error checks and
// the scratch-directory fixture of tests/support.
#pragma once

#include <cstring>

#include "common/ExpectInputError.h"
#include "common/ScratchDirectory.h"

namespace d2vdb::test {

/// True when the two doubles have identical bits (an exact round trip).
inline bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof(double)) == 0;
}

}  // namespace d2vdb::test
