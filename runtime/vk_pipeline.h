#pragma once
// Compute pipelines built once from embedded SPIR-V and reused for every dispatch. Descriptor
// layout convention (all shaders): set 0, bindings 0..num_buffers-1 are storage buffers.
// Kernel families borrow theirs from vk::Context::pipeline(), which builds each distinct
// description once per context; constructing a Pipeline directly gives a private one.
#include <compare>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "runtime/vk_context.h"

namespace pensight::vk {

struct ImplAccess;

struct PipelineDesc {
  std::string shader;                    // embedded name, e.g. "roi_normalize/roi_normalize"
  uint32_t num_buffers = 1;              // storage buffers at bindings 0..num_buffers-1
  uint32_t push_constant_bytes = 0;      // size of the push-constant block (multiple of 4)
  std::vector<uint32_t> specialization;  // value of constant_id = i (ints, or floats as bits)

  // The registry key: two equal descriptions build identical pipelines.
  auto operator<=>(const PipelineDesc&) const = default;
  bool operator==(const PipelineDesc&) const = default;
};

class Pipeline {
 public:
  Pipeline(const Context& ctx, PipelineDesc desc);
  ~Pipeline();
  Pipeline(Pipeline&&) noexcept;
  Pipeline& operator=(Pipeline&&) noexcept;

  const PipelineDesc& desc() const;

  struct Impl;

 private:
  friend struct ImplAccess;  // vk_detail.h: runtime/ sources only
  std::unique_ptr<Impl> impl_;
};

// SPIR-V words of an embedded shader; throws pensight::Error naming the shader if unknown.
std::span<const uint32_t> embedded_shader(const std::string& name);

}  // namespace pensight::vk
