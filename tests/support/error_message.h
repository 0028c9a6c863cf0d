#pragma once
// The message of the pensight::Error a call throws, for tests of what a refusal says.
// Header-only, so tests that link no GPU layer use it too.
#include <string>
#include <utility>

#include "core/error.h"

namespace pensight::testing {

// What `f()` throws as pensight::Error; empty when it throws nothing (any other exception
// propagates and fails the test).
template <class F>
std::string error_message(F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace pensight::testing
