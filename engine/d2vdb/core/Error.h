// Exception types shared by every d2vdb module.
#pragma once

#include <stdexcept>
#include <string>

namespace d2vdb {

/// Base of every exception d2vdb throws. what() is a complete sentence for the user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The input (a file, a parameter, geometry) is malformed, degenerate or out of range.
/// The message names what was wrong and, where there is one, the file and line or byte offset.
/// The command-line tool maps it to exit code 2.
class InputError : public Error {
 public:
  using Error::Error;
};

/// The input was acceptable but the operation could not be completed (I/O failure while writing,
/// a resource limit, an internal limit reached). The command-line tool maps it to exit code 3.
class RuntimeFailure : public Error {
 public:
  using Error::Error;
};

}  // namespace d2vdb
