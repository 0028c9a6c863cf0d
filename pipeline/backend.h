#pragma once
// Which implementation runs the kernels: the native CPU path, Vulkan, or CUDA.
#include <string>
#include <string_view>

namespace pensight {

enum class Backend { kAuto, kCpu, kVulkan, kCuda };

std::string_view to_string(Backend backend);
// "auto", "cpu", "vulkan" or "cuda"; throws pensight::Error listing the choices otherwise.
Backend parse_backend(std::string_view name);

struct ResolvedBackend {
  Backend backend = Backend::kCpu;
  std::string device;  // e.g. "NVIDIA H100", "llvmpipe (LLVM 15.0.6, 256 bits)", "CPU"
  std::string reason;  // why auto chose it
};

// kAuto takes a real GPU when there is one (CUDA first, then a Vulkan GPU) and the native CPU
// path otherwise: lavapipe is Vulkan on the CPU, slower than the native path, and is chosen only
// when asked for. An explicit backend that cannot run here throws pensight::Error saying why.
ResolvedBackend resolve_backend(Backend requested);

}  // namespace pensight
