#pragma once
// The seed of a randomized test: different per run unless PENSIGHT_TEST_SEED is set, printed and
// recorded so that a failure can be reproduced. Header-only, so tests that link no GPU layer
// (the LINKS form of pensight_add_test) use it too.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

namespace pensight::testing {

inline uint64_t fresh_seed() {
  const char* fixed = std::getenv("PENSIGHT_TEST_SEED");
  const uint64_t seed = fixed ? std::strtoull(fixed, nullptr, 10) : std::random_device{}();
  ::testing::Test::RecordProperty("seed", std::to_string(seed));
  std::printf("[ seed     ] PENSIGHT_TEST_SEED=%llu\n", static_cast<unsigned long long>(seed));
  return seed;
}

}  // namespace pensight::testing
