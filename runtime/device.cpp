#include "runtime/device.h"

#include "core/error.h"
#include "runtime/cuda_device.h"

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

Backend choose_backend(Backend requested, Device& device, BackendSupport support) {
  if (requested != Backend::kAuto) return requested;
  if (support.cuda && device.cuda_available()) return Backend::kCuda;
  if (support.vulkan) {
    // No Vulkan loader or device (nullptr) is not an error here: the CPU path is the answer.
    const vk::Context* ctx = device.try_vulkan();
    if (ctx && (support.software_vulkan || vk::is_real_gpu(ctx->info().kind))) {
      return Backend::kVulkan;
    }
  }
  return Backend::kCpu;
}

}  // namespace pensight
