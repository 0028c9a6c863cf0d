#pragma once
// The kernel families' SPIR-V (shaders/fft_roi, shaders/nn, shaders/sparse_prior), embedded in
// pensight_kernels at build time (cmake/PensightShaders.cmake).
#include <string_view>

#include "runtime/vk_pipeline.h"

namespace pensight::kernels {

// The shader at shaders/<name>.comp, e.g. "fft_roi/extract"; throws pensight::Error naming it
// when this layer does not embed it.
vk::ShaderCode kernel_shader(std::string_view name);

}  // namespace pensight::kernels
