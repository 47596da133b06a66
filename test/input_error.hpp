// The message of the InputError a call throws, for tests that check what it
// says; a failure (and "") when it throws none.
#pragma once

#include "risas/errors.hpp"

#include <gtest/gtest.h>

#include <string>

namespace risas::test {

template <class F>
std::string inputErrorOf(F&& call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

}  // namespace risas::test
