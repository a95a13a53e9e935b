// Checking that a call fails with d2vdb::InputError and a message that says what it should.
#pragma once

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb::test {

/// Expects `call` to throw InputError whose message contains every one of `fragments`.
template <typename Call>
void expectInputError(Call&& call, std::initializer_list<std::string> fragments) {
  try {
    call();
    ADD_FAILURE() << "expected an InputError containing '" << *fragments.begin() << "'";
  } catch (const InputError& error) {
    const std::string message = error.what();
    for (const std::string& fragment : fragments) {
      EXPECT_NE(message.find(fragment), std::string::npos)
          << "message \"" << message << "\" lacks \"" << fragment << "\"";
    }
  }
}

}  // namespace d2vdb::test
