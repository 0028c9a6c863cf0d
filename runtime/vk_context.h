#pragma once
// The Vulkan context: instance, one chosen device, its compute queue, the on-disk pipeline cache
// and the in-process pipeline registry. Create one per process (or per device) and share it;
// everything else borrows it.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace pensight::vk {

struct ImplAccess;

struct PipelineDesc;
class Pipeline;

enum class DeviceKind { kDiscrete, kIntegrated, kVirtual, kCpu, kOther };
const char* to_string(DeviceKind kind);
// A GPU of its own (not a CPU driver such as lavapipe): what the automatic backends choose.
inline bool is_real_gpu(DeviceKind kind) {
  return kind == DeviceKind::kDiscrete || kind == DeviceKind::kIntegrated;
}

struct DeviceInfo {
  uint32_t index = 0;  // position in the Vulkan enumeration
  std::string name;
  std::string driver;  // driver name and version string
  DeviceKind kind = DeviceKind::kOther;
  uint32_t vendor_id = 0;
  uint32_t device_id = 0;
  uint32_t api_version = 0;
  bool host_visible_device_memory = false;  // device-local memory the host can map (lavapipe, Orin)
  bool fp16_storage = false;                // storageBuffer16BitAccess
  bool int8_storage = false;                // storageBuffer8BitAccess
  bool timestamps = false;                  // compute queue supports timestamp queries
  float timestamp_period_ns = 0;
  uint32_t subgroup_size = 0;
  bool subgroup_arithmetic = false;  // required: reductions use subgroupAdd
  uint32_t max_workgroup_invocations = 0;
  uint32_t max_shared_memory_bytes = 0;
};

struct ContextOptions {
  // "" chooses automatically: discrete GPU > integrated > virtual > other > CPU (lavapipe).
  // Otherwise a device index ("1") or a case-insensitive substring of its name ("llvmpipe").
  // When empty, the environment variable PENSIGHT_VK_DEVICE is used if set.
  std::string device;
  // Khronos validation layer (debug builds, tests). PENSIGHT_VK_VALIDATION=1 turns it on too.
  bool validation = false;
  // Also enable synchronization validation (missing or wrong barriers), when validation is on.
  bool sync_validation = true;
  // Called for each validation error; the default logs it. Errors are counted either way.
  std::function<void(const std::string&)> on_validation_error;
  // Directory of the persistent pipeline cache; empty = $PENSIGHT_CACHE_DIR, else
  // $XDG_CACHE_HOME/pensight, else ~/.cache/pensight. "-" disables the on-disk cache.
  std::filesystem::path cache_dir;
  // Fault injection for tests of what a lost device does to a run: every queue submission after
  // this many fails with VK_ERROR_DEVICE_LOST, as on a real device after a reset (0: never).
  int lose_device_after_submits = 0;
};

class Context {
 public:
  // Throws pensight::Error with install instructions when there is no Vulkan loader or device.
  explicit Context(ContextOptions options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceInfo& info() const;
  // Number of validation errors reported since creation (0 when validation is off).
  uint64_t validation_errors() const;
  // Writes the pipeline cache to disk now (it is also written on destruction).
  void save_pipeline_cache() const;
  std::filesystem::path pipeline_cache_path() const;

  // The context's one pipeline for `desc` (shader, buffers, push-constant size, specialization),
  // built on the first request and kept until the context is destroyed, so every kernel family
  // and every instance of one borrows the same object and the reference stays valid. Thread-safe:
  // different descriptions build concurrently, the same one is built once while others wait.
  // Throws like the Pipeline constructor; a failed build is retried on the next request.
  const Pipeline& pipeline(const PipelineDesc& desc) const;
  // Distinct pipelines built through pipeline() so far.
  size_t num_pipelines() const;

  // All devices the loader reports; throws like the constructor when there is no loader.
  static std::vector<DeviceInfo> list_devices();

  struct Impl;

 private:
  friend struct ImplAccess;  // vk_detail.h: runtime/ sources only
  std::unique_ptr<Impl> impl_;
};

}  // namespace pensight::vk
