#include "pipeline/backend.h"

#include "runtime/cuda_device.h"
#include "runtime/error.h"
#include "runtime/vk_context.h"

namespace pensight {

std::string_view to_string(Backend backend) {
  switch (backend) {
    case Backend::kAuto:
      return "auto";
    case Backend::kCpu:
      return "cpu";
    case Backend::kVulkan:
      return "vulkan";
    case Backend::kCuda:
      return "cuda";
  }
  return "?";
}

Backend parse_backend(std::string_view name) {
  for (Backend b : {Backend::kAuto, Backend::kCpu, Backend::kVulkan, Backend::kCuda}) {
    if (name == to_string(b)) return b;
  }
  throw Error("unknown backend '" + std::string(name) + "'; choose auto, cpu, vulkan or cuda");
}

ResolvedBackend resolve_backend(Backend requested) {
  switch (requested) {
    case Backend::kCpu:
      return {Backend::kCpu, "CPU", "requested"};
    case Backend::kCuda:
      return {Backend::kCuda, cuda::device_info().name, "requested"};
    case Backend::kVulkan: {
      const vk::Context ctx;  // throws with install instructions when there is no device
      return {Backend::kVulkan, ctx.info().name, "requested"};
    }
    case Backend::kAuto:
      break;
  }
  if (cuda::available()) return {Backend::kCuda, cuda::device_info().name, "CUDA device found"};
  try {
    for (const vk::DeviceInfo& d : vk::Context::list_devices()) {
      if (d.kind == vk::DeviceKind::kDiscrete || d.kind == vk::DeviceKind::kIntegrated) {
        const vk::Context ctx;  // the device the Vulkan path will actually pick
        return {Backend::kVulkan, ctx.info().name, "Vulkan GPU found"};
      }
    }
  } catch (const Error&) {
    // No Vulkan loader or device: the CPU path needs neither.
  }
  return {Backend::kCpu, "CPU", "no GPU found (lavapipe is only used when asked for)"};
}

}  // namespace pensight
