#pragma once
// The renderer's SPIR-V (shaders/sim), embedded in pensight_sim at build time
// (cmake/PensightShaders.cmake).
#include <string_view>

#include "runtime/vk_pipeline.h"

namespace pensight::sim {

// The shader at shaders/<name>.comp, e.g. "sim/render"; throws pensight::Error naming it when
// this layer does not embed it.
vk::ShaderCode sim_shader(std::string_view name);

}  // namespace pensight::sim
