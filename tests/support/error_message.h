#pragma once
// The message of the pensight::Error a call throws, for tests of what a refusal says.
// Header-only, so tests that link no GPU layer use it too.
#include <gtest/gtest.h>

#include <cstddef>
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

// A config spoilt one way, and how the message refusing it starts.
template <class Config>
struct SpoiltConfig {
  const char* message_start;
  void (*spoil)(Config&);
};

// Each case's default Config, spoilt, must be refused by `check(config)` with a message starting
// with `prefix` and the case's message_start.
template <class Config, size_t N, class Check>
void expect_refused(const SpoiltConfig<Config> (&cases)[N], const std::string& prefix,
                    Check check) {
  for (const SpoiltConfig<Config>& c : cases) {
    Config config;
    c.spoil(config);
    const std::string message = error_message([&] { check(config); });
    EXPECT_TRUE(message.starts_with(prefix + c.message_start)) << message;
  }
}

}  // namespace pensight::testing
