#include "tests/support/vulkan_fixture.h"

#include <cstdlib>
#include <memory>
#include <string>

namespace pensight::testing {

vk::ContextOptions test_context_options() {
  vk::ContextOptions options;
  options.validation = true;
  options.sync_validation = true;
  options.cache_dir = "-";  // tests must not depend on a cache left by an earlier run
  options.on_validation_error = [](const std::string& message) {
    ADD_FAILURE() << "Vulkan validation error: " << message;
  };
  return options;
}

Device& test_device() {
  static Device device(test_context_options());
  return device;
}

const vk::Context& VulkanTest::ctx() {
  return test_device().vulkan();
}

uint64_t fresh_seed() {
  const char* fixed = std::getenv("PENSIGHT_TEST_SEED");
  const uint64_t seed = fixed ? std::strtoull(fixed, nullptr, 10) : std::random_device{}();
  ::testing::Test::RecordProperty("seed", std::to_string(seed));
  std::printf("[ seed     ] PENSIGHT_TEST_SEED=%llu\n", static_cast<unsigned long long>(seed));
  return seed;
}

}  // namespace pensight::testing
