#pragma once
// The compute devices of one process: the Vulkan context (opened on first use, then shared by
// every stage and kernel family) and whether CUDA can be used. A vehicle program makes one Device
// and hands it to each stage; no stage opens a context of its own, so pipelines, the pipeline
// cache and device memory are shared.
//
// Thread safety: vulkan() and try_vulkan() may be called from any thread; the context they return
// is as thread-safe as vk::Context (pipelines and buffers yes, one command stream per thread).
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "core/backend.h"
#include "runtime/vk_context.h"

namespace pensight {

class Device {
 public:
  // Nothing is opened here; `vulkan` is used when the context is first asked for.
  explicit Device(vk::ContextOptions vulkan = {});
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  // The Vulkan context. Throws pensight::Error (with the install line) when there is no loader
  // or no device; a failed open is remembered and rethrown, not retried.
  vk::Context& vulkan();
  // The Vulkan context, or nullptr when none opens (the reason is in vulkan_error()).
  vk::Context* try_vulkan();
  // Why no Vulkan context opened; empty when it did or has not been asked for.
  std::string vulkan_error() const;
  // True when built with CUDA and a CUDA device is present (cuda::available()).
  bool cuda_available() const;

 private:
  vk::ContextOptions options_;
  mutable std::mutex mutex_;
  std::unique_ptr<vk::Context> vulkan_;
  std::optional<std::string> vulkan_error_;
};

// What kAuto means for one stage: the back-ends it has beyond the CPU, and whether a software
// Vulkan device (lavapipe) beats its CPU path (the renderer's shader does; the FFT and the depth
// network do not).
struct BackendSupport {
  bool vulkan = true;
  bool cuda = false;
  bool software_vulkan = false;
};

// The backend a stage runs on: `requested` when it is not kAuto (the stage's constructor then
// fails with the reason if the device lacks it), else the first of CUDA, Vulkan and the CPU that
// the stage supports and the device offers. Vulkan counts only on a real GPU unless
// software_vulkan. Opens the Vulkan context to look (Device::try_vulkan); never throws for a
// device that is missing.
Backend choose_backend(Backend requested, Device& device, BackendSupport support);

}  // namespace pensight
