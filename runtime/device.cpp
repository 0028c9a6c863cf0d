#include "runtime/device.h"

#include "runtime/cuda_device.h"
#include "runtime/error.h"

namespace pensight {

Device::Device(vk::ContextOptions vulkan) : options_(std::move(vulkan)) {}
Device::~Device() = default;

vk::Context* Device::try_vulkan() {
  std::lock_guard lock(mutex_);
  if (!vulkan_ && !vulkan_error_) {
    try {
      vulkan_ = std::make_unique<vk::Context>(options_);
    } catch (const Error& e) {
      vulkan_error_ = e.what();
    }
  }
  return vulkan_.get();
}

vk::Context& Device::vulkan() {
  if (vk::Context* ctx = try_vulkan()) return *ctx;
  throw Error(vulkan_error());
}

std::string Device::vulkan_error() const {
  std::lock_guard lock(mutex_);
  return vulkan_error_.value_or("");
}

bool Device::cuda_available() const {
  return cuda::available();
}

}  // namespace pensight
