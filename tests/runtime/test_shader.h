#pragma once
// The runtime tests' SPIR-V (tests/runtime/shaders/), embedded in runtime_test only.
#include <string_view>

#include "runtime/vk_pipeline.h"

namespace pensight::testing {

vk::ShaderCode test_shader(std::string_view name);

}  // namespace pensight::testing
