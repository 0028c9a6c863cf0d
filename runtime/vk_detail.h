#pragma once
// Internal to runtime/: the Vulkan handles behind the public classes. Nothing outside runtime/
// includes this header.
#include <volk.h>

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "runtime/vk_buffer.h"
#include "runtime/vk_context.h"
#include "runtime/vk_pipeline.h"

namespace pensight::vk {

const char* result_name(VkResult r);
// Throws VulkanError naming `call` unless r is VK_SUCCESS.
void check(VkResult r, const char* call);
#define PENSIGHT_VK(call) ::pensight::vk::check((call), #call)

// The pipelines of one context, one per distinct description. std::map nodes never move, so the
// references Context::pipeline() hands out stay valid until the registry is cleared. The map
// mutex is held only to find or insert an entry; each entry's own mutex serialises its build, so
// slow driver compiles of different pipelines run in parallel.
struct PipelineRegistry {
  struct Entry {
    std::mutex build;
    std::unique_ptr<Pipeline> pipeline;
  };
  std::mutex mutex;
  std::map<PipelineDesc, Entry> entries;
  std::atomic<size_t> built{0};
};

struct Context::Impl {
  ContextOptions options;
  DeviceInfo info;
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger = nullptr;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VolkDeviceTable vk{};
  uint32_t queue_family = 0;
  VkQueue queue = VK_NULL_HANDLE;
  mutable std::mutex queue_mutex;  // vkQueueSubmit needs external synchronisation
  mutable int submits = 0;         // under queue_mutex (ContextOptions::lose_device_after_submits)
  VkPipelineCache pipeline_cache = VK_NULL_HANDLE;
  std::filesystem::path cache_path;
  VkPhysicalDeviceMemoryProperties memory{};
  std::atomic<uint64_t> validation_errors{0};
  PipelineRegistry pipelines;
  ~Impl();

  // Index of a memory type allowed by `type_bits` with all of `required` (and as many of
  // `preferred` as possible); throws when none fits.
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                       VkMemoryPropertyFlags preferred) const;
  // Submits one command buffer to the compute queue (thread-safe) and waits for `fence`.
  void submit_and_wait(VkCommandBuffer cmd, VkFence fence) const;
};

struct Buffer::Impl {
  const Context::Impl* ctx = nullptr;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
  size_t size = 0;
  bool coherent = true;
  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl();
};

struct Pipeline::Impl {
  const Context::Impl* ctx = nullptr;
  PipelineDesc desc;
  VkShaderModule module = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl();
};

// A transient command pool + buffer for one-off work (staging copies).
// The one way to a runtime class's Impl: vk_detail.h is included by runtime/ sources only, so
// nothing outside runtime/ reaches Vulkan handles through the public classes.
struct ImplAccess {
  static Context::Impl& of(const Context& c) { return *c.impl_; }
  static Buffer::Impl& of(const Buffer& b) { return *b.impl_; }
  static Pipeline::Impl& of(const Pipeline& p) { return *p.impl_; }
};

class OneShot {
 public:
  explicit OneShot(const Context::Impl& ctx);
  ~OneShot();
  VkCommandBuffer cmd() const { return cmd_; }
  void submit_and_wait();

 private:
  const Context::Impl& ctx_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
};

}  // namespace pensight::vk
