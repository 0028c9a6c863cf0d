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

}  // namespace pensight::testing
