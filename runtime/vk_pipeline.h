#pragma once
// Compute pipelines built once from embedded SPIR-V and reused for every dispatch. Descriptor
// layout convention (all shaders): set 0, bindings 0..num_buffers-1 are storage buffers.
// Kernel families borrow theirs from vk::Context::pipeline(), which builds each distinct
// description once per context; constructing a Pipeline directly gives a private one. The SPIR-V
// is embedded by the layer that dispatches it (cmake/PensightShaders.cmake), not by the runtime.
#include <compare>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/vk_context.h"

namespace pensight::vk {

struct ImplAccess;

// One entry of a layer's embedded shader table.
struct EmbeddedShader {
  std::string_view name;  // path under shaders/ without extension, e.g. "fft_roi/extract"
  std::span<const uint32_t> spirv;
};

// A shader's name and its SPIR-V words, which outlive every pipeline (a layer's static table).
// The name is the identity: two ShaderCodes of one name hold the same words.
struct ShaderCode {
  std::string_view name;
  std::span<const uint32_t> spirv;

  std::strong_ordering operator<=>(const ShaderCode& o) const { return name <=> o.name; }
  bool operator==(const ShaderCode& o) const { return name == o.name; }
};

// The shader `name` of a layer's table; throws pensight::Error naming it and `layer` if absent.
ShaderCode find_shader(std::span<const EmbeddedShader> table, std::string_view name,
                       std::string_view layer);

struct PipelineDesc {
  ShaderCode shader;                     // from the dispatching layer's table
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

}  // namespace pensight::vk
