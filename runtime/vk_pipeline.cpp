#include <algorithm>
#include <string>
#include <utility>

#include "core/error.h"
#include "runtime/vk_detail.h"

namespace pensight::vk {

ShaderCode find_shader(std::span<const EmbeddedShader> table, std::string_view name,
                       std::string_view layer) {
  for (const EmbeddedShader& s : table) {
    if (s.name == name) return {s.name, s.spirv};
  }
  throw Error("no embedded shader named '" + std::string(name) + "' in " + std::string(layer) +
              " (shaders/" + std::string(name) + ".comp is not embedded by that layer)");
}

Pipeline::Impl::~Impl() {
  if (!ctx) return;
  const auto& vk = ctx->vk;
  if (pipeline) vk.vkDestroyPipeline(ctx->device, pipeline, nullptr);
  if (layout) vk.vkDestroyPipelineLayout(ctx->device, layout, nullptr);
  if (set_layout) vk.vkDestroyDescriptorSetLayout(ctx->device, set_layout, nullptr);
  if (module) vk.vkDestroyShaderModule(ctx->device, module, nullptr);
}

Pipeline::Pipeline(const Context& ctx, PipelineDesc desc) : impl_(std::make_unique<Impl>()) {
  Impl& p = *impl_;
  const Context::Impl& c = ImplAccess::of(ctx);
  p.ctx = &c;
  p.desc = std::move(desc);
  if (p.desc.push_constant_bytes % 4 != 0) {
    throw Error("pipeline '" + std::string(p.desc.shader.name) +
                "': push_constant_bytes must be a multiple of 4");
  }
  // SPIR-V starts with its magic number; anything else would reach the driver as garbage.
  constexpr uint32_t kSpirvMagic = 0x07230203;
  const std::span<const uint32_t> code = p.desc.shader.spirv;
  if (code.size() < 5 || code[0] != kSpirvMagic) {
    throw Error("pipeline '" + std::string(p.desc.shader.name) +
                "': its code is not SPIR-V; take it from the layer's embedded shader table");
  }

  VkShaderModuleCreateInfo smci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smci.codeSize = code.size_bytes();
  smci.pCode = code.data();
  PENSIGHT_VK(c.vk.vkCreateShaderModule(c.device, &smci, nullptr, &p.module));

  std::vector<VkDescriptorSetLayoutBinding> bindings(p.desc.num_buffers);
  for (uint32_t i = 0; i < p.desc.num_buffers; ++i) {
    bindings[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  }
  VkDescriptorSetLayoutCreateInfo dslci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dslci.bindingCount = p.desc.num_buffers;
  dslci.pBindings = bindings.data();
  PENSIGHT_VK(c.vk.vkCreateDescriptorSetLayout(c.device, &dslci, nullptr, &p.set_layout));

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, p.desc.push_constant_bytes};
  VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  plci.setLayoutCount = 1;
  plci.pSetLayouts = &p.set_layout;
  plci.pushConstantRangeCount = p.desc.push_constant_bytes ? 1 : 0;
  plci.pPushConstantRanges = &range;
  PENSIGHT_VK(c.vk.vkCreatePipelineLayout(c.device, &plci, nullptr, &p.layout));

  std::vector<VkSpecializationMapEntry> entries(p.desc.specialization.size());
  for (uint32_t i = 0; i < entries.size(); ++i) {
    entries[i] = {i, static_cast<uint32_t>(i * sizeof(uint32_t)), sizeof(uint32_t)};
  }
  VkSpecializationInfo spec{static_cast<uint32_t>(entries.size()), entries.data(),
                            p.desc.specialization.size() * sizeof(uint32_t),
                            p.desc.specialization.data()};
  VkComputePipelineCreateInfo cpci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  cpci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cpci.stage.module = p.module;
  cpci.stage.pName = "main";
  cpci.stage.pSpecializationInfo = entries.empty() ? nullptr : &spec;
  cpci.layout = p.layout;
  const VkResult r =
      c.vk.vkCreateComputePipelines(c.device, c.pipeline_cache, 1, &cpci, nullptr, &p.pipeline);
  if (r != VK_SUCCESS) {
    throw VulkanError("vkCreateComputePipelines('" + std::string(p.desc.shader.name) + "')", r);
  }
}

Pipeline::~Pipeline() = default;
Pipeline::Pipeline(Pipeline&&) noexcept = default;
Pipeline& Pipeline::operator=(Pipeline&&) noexcept = default;

const PipelineDesc& Pipeline::desc() const {
  return impl_->desc;
}

const Pipeline& Context::pipeline(const PipelineDesc& desc) const {
  PipelineRegistry& r = impl_->pipelines;
  PipelineRegistry::Entry* entry;
  {
    std::lock_guard lock(r.mutex);
    entry = &r.entries.try_emplace(desc).first->second;
  }
  std::lock_guard lock(entry->build);
  if (!entry->pipeline) {
    entry->pipeline = std::make_unique<Pipeline>(*this, desc);
    ++r.built;
  }
  return *entry->pipeline;
}

size_t Context::num_pipelines() const {
  return impl_->pipelines.built.load();
}

}  // namespace pensight::vk
