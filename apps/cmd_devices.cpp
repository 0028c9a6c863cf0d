#include <cstdio>

#include "apps/command.h"
#include "core/error.h"
#include "runtime/cuda_device.h"
#include "runtime/vk_context.h"

namespace pensight::app {

int cmd_devices(const Args&) {
  try {
    for (const vk::DeviceInfo& d : vk::Context::list_devices()) {
      std::printf(
          "vulkan %u: %s (%s), driver %s, host-visible device memory: %s, fp16 storage: %s\n",
          d.index, d.name.c_str(), vk::to_string(d.kind), d.driver.c_str(),
          d.host_visible_device_memory ? "yes" : "no", d.fp16_storage ? "yes" : "no");
    }
    const vk::Context ctx;
    std::printf("chosen: vulkan %u (%s)\n", ctx.info().index, ctx.info().name.c_str());
  } catch (const Error& e) {
    std::printf("vulkan: %s\n", e.what());
  }
  if (cuda::available()) {
    const cuda::DeviceInfo d = cuda::device_info();
    std::printf("cuda 0: %s, sm_%d%d, %.1f GiB\n", d.name.c_str(), d.compute_major, d.compute_minor,
                static_cast<double>(d.memory_bytes) / (1 << 30));
  } else {
    std::printf("cuda: none%s\n", PENSIGHT_HAS_CUDA ? "" : " (built without CUDA)");
  }
  return 0;
}

PENSIGHT_COMMAND("devices", "list Vulkan and CUDA devices and the one pensight would choose",
                 cmd_devices);

}  // namespace pensight::app
