#include "runtime/vk_stream.h"

#include <algorithm>
#include <map>

#include "core/error.h"
#include "runtime/vk_detail.h"

namespace pensight::vk {
namespace {

// Descriptor sets are allocated from pools of this many; a stream rarely needs a second pool.
constexpr uint32_t kSetsPerPool = 64;
constexpr uint32_t kBuffersPerPool = kSetsPerPool * 8;

// Hazard tracking since the last barrier, per buffer.
struct BufferState {
  bool written = false;  // written by a command after the last barrier
  bool read = false;     // read by a command after the last barrier
};

}  // namespace

struct CommandStream::Impl {
  const Context::Impl* ctx;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  std::vector<VkDescriptorPool> descriptor_pools;
  uint32_t sets_in_last_pool = kSetsPerPool;
  VkQueryPool queries = VK_NULL_HANDLE;
  uint32_t query_capacity = 0;
  bool recording = false;
  bool ended = false;
  std::vector<std::string> names;
  std::map<VkBuffer, BufferState> states;
  std::vector<DispatchTime> last_timings;
  bool timestamps = false;
  size_t barriers = 0;

  ~Impl() {
    const auto& vk = ctx->vk;
    for (VkDescriptorPool p : descriptor_pools) vk.vkDestroyDescriptorPool(ctx->device, p, nullptr);
    if (queries) vk.vkDestroyQueryPool(ctx->device, queries, nullptr);
    if (fence) vk.vkDestroyFence(ctx->device, fence, nullptr);
    if (pool) vk.vkDestroyCommandPool(ctx->device, pool, nullptr);
  }

  void begin() {
    if (recording) return;
    if (ended) throw Error("vk::CommandStream: call reset() before recording after a submit");
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    PENSIGHT_VK(ctx->vk.vkBeginCommandBuffer(cmd, &bi));
    recording = true;
    if (timestamps) {
      ctx->vk.vkCmdResetQueryPool(cmd, queries, 0, query_capacity);
      timestamp(0);
    }
  }

  VkDescriptorSet allocate_set(VkDescriptorSetLayout layout) {
    if (sets_in_last_pool == kSetsPerPool) {
      VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kBuffersPerPool};
      VkDescriptorPoolCreateInfo ci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
      ci.maxSets = kSetsPerPool;
      ci.poolSizeCount = 1;
      ci.pPoolSizes = &size;
      VkDescriptorPool p = VK_NULL_HANDLE;
      PENSIGHT_VK(ctx->vk.vkCreateDescriptorPool(ctx->device, &ci, nullptr, &p));
      descriptor_pools.push_back(p);
      sets_in_last_pool = 0;
    }
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = descriptor_pools.back();
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &layout;
    VkDescriptorSet set = VK_NULL_HANDLE;
    PENSIGHT_VK(ctx->vk.vkAllocateDescriptorSets(ctx->device, &ai, &set));
    ++sets_in_last_pool;
    return set;
  }

  // Emits one global memory barrier if any access conflicts with an earlier unsynchronised one.
  // A global barrier (rather than per-buffer ones) is what vendors recommend for compute chains.
  void sync(const std::vector<std::pair<VkBuffer, Access>>& accesses) {
    bool hazard = false;
    for (const auto& [buffer, access] : accesses) {
      const BufferState& s = states[buffer];
      const bool writes = access != Access::kRead;
      if (s.written || (writes && s.read)) hazard = true;
    }
    if (hazard) {
      VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
      barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
      barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                              VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
      const VkPipelineStageFlags stages =
          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
      ctx->vk.vkCmdPipelineBarrier(cmd, stages, stages, 0, 1, &barrier, 0, nullptr, 0, nullptr);
      states.clear();
      ++barriers;
    }
    for (const auto& [buffer, access] : accesses) {
      BufferState& s = states[buffer];
      if (access != Access::kRead) s.written = true;
      if (access != Access::kWrite) s.read = true;
    }
  }

  // Past the pool's capacity commands still run, only their timings are not reported.
  void timestamp(uint32_t index) {
    if (!timestamps || index >= query_capacity) return;
    ctx->vk.vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries, index);
  }
};

CommandStream::CommandStream(const Context& ctx) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.ctx = &ImplAccess::of(ctx);
  const auto& vk = s.ctx->vk;
  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = s.ctx->queue_family;
  PENSIGHT_VK(vk.vkCreateCommandPool(s.ctx->device, &pci, nullptr, &s.pool));
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = s.pool;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  PENSIGHT_VK(vk.vkAllocateCommandBuffers(s.ctx->device, &ai, &s.cmd));
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  PENSIGHT_VK(vk.vkCreateFence(s.ctx->device, &fci, nullptr, &s.fence));
  s.timestamps = s.ctx->info.timestamps;
  if (s.timestamps) {
    s.query_capacity = 256;
    VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qci.queryCount = s.query_capacity;
    PENSIGHT_VK(vk.vkCreateQueryPool(s.ctx->device, &qci, nullptr, &s.queries));
  }
}

CommandStream::~CommandStream() = default;

size_t CommandStream::num_commands() const {
  return impl_->names.size();
}
size_t CommandStream::num_barriers() const {
  return impl_->barriers;
}

void CommandStream::dispatch(const Pipeline& pipeline, std::span<const Binding> buffers,
                             Groups groups, const void* push_constants, size_t push_bytes,
                             std::string name) {
  Impl& s = *impl_;
  const Pipeline::Impl& p = ImplAccess::of(pipeline);
  if (buffers.size() != p.desc.num_buffers) {
    throw Error("dispatch of '" + std::string(p.desc.shader.name) +
                "': " + std::to_string(buffers.size()) + " buffers bound, the pipeline has " +
                std::to_string(p.desc.num_buffers));
  }
  if (push_bytes != p.desc.push_constant_bytes) {
    throw Error("dispatch of '" + std::string(p.desc.shader.name) +
                "': " + std::to_string(push_bytes) + " push-constant bytes, the pipeline expects " +
                std::to_string(p.desc.push_constant_bytes));
  }
  if (groups.x == 0 || groups.y == 0 || groups.z == 0) return;
  s.begin();

  VkDescriptorSet set = s.allocate_set(p.set_layout);
  std::vector<VkDescriptorBufferInfo> infos;
  std::vector<std::pair<VkBuffer, Access>> accesses;
  infos.reserve(buffers.size());
  for (const Binding& b : buffers) {
    infos.push_back({ImplAccess::of(*b.buffer).buffer, 0, VK_WHOLE_SIZE});
    accesses.emplace_back(ImplAccess::of(*b.buffer).buffer, b.access);
  }
  std::vector<VkWriteDescriptorSet> writes(infos.size());
  for (uint32_t i = 0; i < infos.size(); ++i) {
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  s.ctx->vk.vkUpdateDescriptorSets(s.ctx->device, static_cast<uint32_t>(writes.size()),
                                   writes.data(), 0, nullptr);

  s.sync(accesses);
  s.ctx->vk.vkCmdBindPipeline(s.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
  s.ctx->vk.vkCmdBindDescriptorSets(s.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout, 0, 1, &set, 0,
                                    nullptr);
  if (push_bytes) {
    s.ctx->vk.vkCmdPushConstants(s.cmd, p.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                                 static_cast<uint32_t>(push_bytes), push_constants);
  }
  s.ctx->vk.vkCmdDispatch(s.cmd, groups.x, groups.y, groups.z);
  s.names.push_back(name.empty() ? std::string(p.desc.shader.name) : std::move(name));
  s.timestamp(static_cast<uint32_t>(s.names.size()));
}

void CommandStream::copy(const Buffer& src, const Buffer& dst, size_t bytes, size_t src_offset,
                         size_t dst_offset) {
  Impl& s = *impl_;
  if (bytes == 0) bytes = src.size_bytes() - std::min(src_offset, src.size_bytes());
  if (src_offset + bytes > src.size_bytes() || dst_offset + bytes > dst.size_bytes()) {
    throw Error("vk::CommandStream::copy: " + std::to_string(bytes) +
                " bytes do not fit the source or destination buffer");
  }
  s.begin();
  s.sync(
      {{ImplAccess::of(src).buffer, Access::kRead}, {ImplAccess::of(dst).buffer, Access::kWrite}});
  VkBufferCopy region{src_offset, dst_offset, bytes};
  s.ctx->vk.vkCmdCopyBuffer(s.cmd, ImplAccess::of(src).buffer, ImplAccess::of(dst).buffer, 1,
                            &region);
  s.names.push_back("copy");
  s.timestamp(static_cast<uint32_t>(s.names.size()));
}

void CommandStream::submit_and_wait() {
  Impl& s = *impl_;
  if (s.names.empty()) return;
  if (s.recording) {
    // Device writes must be made visible to the host before it maps and reads the results.
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    s.ctx->vk.vkCmdPipelineBarrier(
        s.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
        VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
    PENSIGHT_VK(s.ctx->vk.vkEndCommandBuffer(s.cmd));
    s.recording = false;
    s.ended = true;
  }
  PENSIGHT_VK(s.ctx->vk.vkResetFences(s.ctx->device, 1, &s.fence));
  s.ctx->submit_and_wait(s.cmd, s.fence);

  s.last_timings.clear();
  if (!s.timestamps) return;
  const uint32_t n =
      std::min<uint32_t>(static_cast<uint32_t>(s.names.size()) + 1, s.query_capacity);
  std::vector<uint64_t> ticks(n);
  PENSIGHT_VK(s.ctx->vk.vkGetQueryPoolResults(
      s.ctx->device, s.queries, 0, n, ticks.size() * sizeof(uint64_t), ticks.data(),
      sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  const double ms_per_tick = s.ctx->info.timestamp_period_ns * 1e-6;
  for (uint32_t i = 1; i < n; ++i) {
    s.last_timings.push_back(
        {s.names[i - 1], static_cast<double>(ticks[i] - ticks[i - 1]) * ms_per_tick});
  }
}

void CommandStream::reset() {
  Impl& s = *impl_;
  if (s.recording) PENSIGHT_VK(s.ctx->vk.vkEndCommandBuffer(s.cmd));
  PENSIGHT_VK(s.ctx->vk.vkResetCommandBuffer(s.cmd, 0));
  for (VkDescriptorPool p : s.descriptor_pools) {
    s.ctx->vk.vkDestroyDescriptorPool(s.ctx->device, p, nullptr);
  }
  s.descriptor_pools.clear();
  s.sets_in_last_pool = kSetsPerPool;
  s.recording = false;
  s.ended = false;
  s.names.clear();
  s.states.clear();
  s.barriers = 0;
  s.last_timings.clear();
}

std::vector<DispatchTime> CommandStream::timings() const {
  return impl_->last_timings;
}

}  // namespace pensight::vk
