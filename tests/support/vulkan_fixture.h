#pragma once
// Test fixture for everything that runs on Vulkan: one shared device per test binary, its context
// created with the Khronos validation layer (synchronization validation included). Every validation
// error becomes a failure of the test that was running.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "runtime/device.h"
#include "runtime/vk_context.h"
#include "tests/support/test_seed.h"

namespace pensight::testing {

// The test binary's one Device; its Vulkan context has validation on (see VulkanTest).
Device& test_device();
// The options of that context, for a test that needs a Device of its own.
vk::ContextOptions test_context_options();

class VulkanTest : public ::testing::Test {
 protected:
  static const vk::Context& ctx();
};

inline constexpr float kPoison = std::numeric_limits<float>::quiet_NaN();

}  // namespace pensight::testing
