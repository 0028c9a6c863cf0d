#include <cstring>
#include <string>

#include "core/error.h"
#include "runtime/vk_detail.h"

namespace pensight::vk {
namespace {

void check_range(size_t offset, size_t bytes, size_t size, const char* what) {
  if (offset > size || bytes > size - offset) {
    throw Error(std::string(what) + ": range [" + std::to_string(offset) + ", +" +
                std::to_string(bytes) + ") is outside the buffer of " + std::to_string(size) +
                " bytes");
  }
}

// Creates the buffer and its memory into `b` (which cleans up whatever was created on failure).
void init_buffer(Buffer::Impl& b, const Context::Impl& ctx, size_t size, VkBufferUsageFlags usage,
                 VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) {
  b.ctx = &ctx;
  b.size = size;
  VkBufferCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  ci.size = size;
  ci.usage = usage;
  ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  PENSIGHT_VK(ctx.vk.vkCreateBuffer(ctx.device, &ci, nullptr, &b.buffer));
  VkMemoryRequirements req;
  ctx.vk.vkGetBufferMemoryRequirements(ctx.device, b.buffer, &req);
  // One allocation per buffer: pensight allocates a handful of long-lived buffers per pipeline,
  // far below maxMemoryAllocationCount, so a sub-allocator would buy nothing.
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, required, preferred);
  PENSIGHT_VK(ctx.vk.vkAllocateMemory(ctx.device, &ai, nullptr, &b.memory));
  PENSIGHT_VK(ctx.vk.vkBindBufferMemory(ctx.device, b.buffer, b.memory, 0));
  const VkMemoryPropertyFlags flags = ctx.memory.memoryTypes[ai.memoryTypeIndex].propertyFlags;
  if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
    PENSIGHT_VK(ctx.vk.vkMapMemory(ctx.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped));
    b.coherent = flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  }
}

constexpr VkBufferUsageFlags kStorageUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                             VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                             VK_BUFFER_USAGE_TRANSFER_DST_BIT;

void copy_via_staging(const Context::Impl& ctx, VkBuffer src, VkBuffer dst, size_t src_offset,
                      size_t dst_offset, size_t bytes) {
  OneShot once(ctx);
  VkBufferCopy region{src_offset, dst_offset, bytes};
  ctx.vk.vkCmdCopyBuffer(once.cmd(), src, dst, 1, &region);
  // Make the transfer visible to later shader work and to the host.
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask =
      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT;
  ctx.vk.vkCmdPipelineBarrier(once.cmd(), VK_PIPELINE_STAGE_TRANSFER_BIT,
                              VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT, 0,
                              1, &barrier, 0, nullptr, 0, nullptr);
  once.submit_and_wait();
}

}  // namespace

Buffer::Impl::~Impl() {
  if (!ctx) return;
  if (mapped) ctx->vk.vkUnmapMemory(ctx->device, memory);
  if (buffer) ctx->vk.vkDestroyBuffer(ctx->device, buffer, nullptr);
  if (memory) ctx->vk.vkFreeMemory(ctx->device, memory, nullptr);
}

Buffer::Buffer(const Context& ctx, size_t size_bytes, MemoryUsage usage)
    : impl_(std::make_unique<Impl>()) {
  if (size_bytes == 0) throw Error("vk::Buffer: size must be > 0");
  const Context::Impl& c = ImplAccess::of(ctx);
  const VkMemoryPropertyFlags local = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  const VkMemoryPropertyFlags host =
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  if (usage == MemoryUsage::kReadback) {
    init_buffer(*impl_, c, size_bytes, kStorageUsage, host, VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
  } else if (c.info.host_visible_device_memory) {
    init_buffer(*impl_, c, size_bytes, kStorageUsage, local, host);
  } else {
    init_buffer(*impl_, c, size_bytes, kStorageUsage, local, 0);
  }
}

Buffer::~Buffer() = default;
Buffer::Buffer(Buffer&&) noexcept = default;
Buffer& Buffer::operator=(Buffer&&) noexcept = default;

size_t Buffer::size_bytes() const {
  return impl_->size;
}
bool Buffer::host_mapped() const {
  return impl_->mapped != nullptr;
}

void Buffer::upload(const void* src, size_t bytes, size_t offset) {
  Impl& b = *impl_;
  check_range(offset, bytes, b.size, "vk::Buffer::upload");
  if (bytes == 0) return;
  if (b.mapped) {
    std::memcpy(static_cast<char*>(b.mapped) + offset, src, bytes);
    if (!b.coherent) {
      VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, b.memory, 0,
                                VK_WHOLE_SIZE};
      PENSIGHT_VK(b.ctx->vk.vkFlushMappedMemoryRanges(b.ctx->device, 1, &range));
    }
    return;
  }
  Impl staging;
  init_buffer(staging, *b.ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
              VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, 0);
  std::memcpy(staging.mapped, src, bytes);
  copy_via_staging(*b.ctx, staging.buffer, b.buffer, 0, offset, bytes);
}

void Buffer::download(void* dst, size_t bytes, size_t offset) const {
  const Impl& b = *impl_;
  check_range(offset, bytes, b.size, "vk::Buffer::download");
  if (bytes == 0) return;
  if (b.mapped) {
    if (!b.coherent) {
      VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, b.memory, 0,
                                VK_WHOLE_SIZE};
      PENSIGHT_VK(b.ctx->vk.vkInvalidateMappedMemoryRanges(b.ctx->device, 1, &range));
    }
    std::memcpy(dst, static_cast<const char*>(b.mapped) + offset, bytes);
    return;
  }
  Impl staging;
  init_buffer(staging, *b.ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
              VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
              VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
  copy_via_staging(*b.ctx, b.buffer, staging.buffer, offset, 0, bytes);
  std::memcpy(dst, staging.mapped, bytes);
}

}  // namespace pensight::vk
