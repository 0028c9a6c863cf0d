#include "core/error.h"
#include "runtime/vk_detail.h"

namespace pensight {

VulkanError::VulkanError(const std::string& call, int result)
    : Error(call + " failed: " + vk::result_name(static_cast<VkResult>(result))), result_(result) {}

namespace vk {

const char* result_name(VkResult r) {
  switch (r) {
#define PENSIGHT_CASE(x) \
  case x:                \
    return #x;
    PENSIGHT_CASE(VK_SUCCESS)
    PENSIGHT_CASE(VK_NOT_READY)
    PENSIGHT_CASE(VK_TIMEOUT)
    PENSIGHT_CASE(VK_INCOMPLETE)
    PENSIGHT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    PENSIGHT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    PENSIGHT_CASE(VK_ERROR_INITIALIZATION_FAILED)
    PENSIGHT_CASE(VK_ERROR_DEVICE_LOST)
    PENSIGHT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    PENSIGHT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    PENSIGHT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    PENSIGHT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    PENSIGHT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    PENSIGHT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    PENSIGHT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    PENSIGHT_CASE(VK_ERROR_FRAGMENTED_POOL)
    PENSIGHT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    PENSIGHT_CASE(VK_ERROR_INVALID_SHADER_NV)
    PENSIGHT_CASE(VK_ERROR_UNKNOWN)
#undef PENSIGHT_CASE
    default:
      return "VkResult(unknown)";
  }
}

void check(VkResult r, const char* call) {
  if (r == VK_ERROR_DEVICE_LOST) {
    throw DeviceLostError(std::string(call) +
                          " failed: VK_ERROR_DEVICE_LOST (the GPU was reset or hung); restart the "
                          "program, or run on the CPU (--backend cpu)");
  }
  if (r != VK_SUCCESS) throw VulkanError(call, r);
}

OneShot::OneShot(const Context::Impl& ctx) : ctx_(ctx) {
  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  pci.queueFamilyIndex = ctx.queue_family;
  PENSIGHT_VK(ctx.vk.vkCreateCommandPool(ctx.device, &pci, nullptr, &pool_));
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  try {
    PENSIGHT_VK(ctx.vk.vkAllocateCommandBuffers(ctx.device, &ai, &cmd_));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    PENSIGHT_VK(ctx.vk.vkBeginCommandBuffer(cmd_, &bi));
  } catch (...) {
    ctx.vk.vkDestroyCommandPool(ctx.device, pool_, nullptr);
    throw;
  }
}

OneShot::~OneShot() {
  ctx_.vk.vkDestroyCommandPool(ctx_.device, pool_, nullptr);
}

void OneShot::submit_and_wait() {
  PENSIGHT_VK(ctx_.vk.vkEndCommandBuffer(cmd_));
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  PENSIGHT_VK(ctx_.vk.vkCreateFence(ctx_.device, &fci, nullptr, &fence));
  try {
    ctx_.submit_and_wait(cmd_, fence);
  } catch (...) {
    ctx_.vk.vkDestroyFence(ctx_.device, fence, nullptr);
    throw;
  }
  ctx_.vk.vkDestroyFence(ctx_.device, fence, nullptr);
}

}  // namespace vk
}  // namespace pensight
