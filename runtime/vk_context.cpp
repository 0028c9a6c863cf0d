#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/file_bytes.h"
#include "core/log.h"
#include "runtime/cache_dir.h"
#include "runtime/vk_detail.h"

namespace pensight::vk {
namespace {

constexpr const char* kInstallHint =
    "Install a Vulkan driver: on Debian/Ubuntu `apt-get install libvulkan1 mesa-vulkan-drivers` "
    "gives lavapipe (Vulkan on the CPU); on NVIDIA machines install the NVIDIA driver. Or run "
    "with --backend cpu.";

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : fallback;
}

void init_loader() {
  static const VkResult r = volkInitialize();
  if (r != VK_SUCCESS) {
    throw Error(std::string("no Vulkan loader (libvulkan.so.1) could be loaded. ") + kInstallHint);
  }
}

DeviceKind kind_of(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return DeviceKind::kDiscrete;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return DeviceKind::kIntegrated;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return DeviceKind::kVirtual;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return DeviceKind::kCpu;
    default:
      return DeviceKind::kOther;
  }
}

int preference(DeviceKind k) {
  switch (k) {
    case DeviceKind::kDiscrete:
      return 0;
    case DeviceKind::kIntegrated:
      return 1;
    case DeviceKind::kVirtual:
      return 2;
    case DeviceKind::kOther:
      return 3;
    case DeviceKind::kCpu:
      return 4;
  }
  return 5;
}

int compute_queue_family(VkPhysicalDevice pd, bool* timestamps) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
  int best = -1;
  for (uint32_t i = 0; i < n; ++i) {
    if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
    // Prefer a family with timestamps; among those the first (usually the universal queue).
    if (best < 0 || (families[i].timestampValidBits && !families[best].timestampValidBits)) {
      best = static_cast<int>(i);
    }
  }
  if (best >= 0 && timestamps) *timestamps = families[best].timestampValidBits > 0;
  return best;
}

DeviceInfo describe(VkPhysicalDevice pd, uint32_t index) {
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceSubgroupProperties subgroup{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  subgroup.pNext = &driver;
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props.pNext = &subgroup;
  vkGetPhysicalDeviceProperties2(pd, &props);

  VkPhysicalDeviceVulkan11Features f11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  f11.pNext = &f12;
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  features.pNext = &f11;
  vkGetPhysicalDeviceFeatures2(pd, &features);

  VkPhysicalDeviceMemoryProperties mem;
  vkGetPhysicalDeviceMemoryProperties(pd, &mem);

  DeviceInfo info;
  info.index = index;
  info.name = props.properties.deviceName;
  info.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  info.kind = kind_of(props.properties.deviceType);
  info.vendor_id = props.properties.vendorID;
  info.device_id = props.properties.deviceID;
  info.api_version = props.properties.apiVersion;
  const VkMemoryPropertyFlags both =
      VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
  for (uint32_t i = 0; i < mem.memoryTypeCount; ++i) {
    const auto& t = mem.memoryTypes[i];
    // A small BAR window is not worth using for whole frames; require it to cover most of VRAM.
    if ((t.propertyFlags & both) == both && mem.memoryHeaps[t.heapIndex].size >= (256ull << 20)) {
      info.host_visible_device_memory = true;
    }
  }
  info.fp16_storage = f11.storageBuffer16BitAccess;
  info.int8_storage = f12.storageBuffer8BitAccess;
  compute_queue_family(pd, &info.timestamps);
  info.timestamp_period_ns = props.properties.limits.timestampPeriod;
  info.subgroup_size = subgroup.subgroupSize;
  info.subgroup_arithmetic = (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                             (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT);
  info.max_workgroup_invocations = props.properties.limits.maxComputeWorkGroupInvocations;
  info.max_shared_memory_bytes = props.properties.limits.maxComputeSharedMemorySize;
  return info;
}

VKAPI_ATTR VkBool32 VKAPI_CALL on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                VkDebugUtilsMessageTypeFlagsEXT,
                                                const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                void* user) {
  auto* impl = static_cast<Context::Impl*>(user);
  const std::string message = data && data->pMessage ? data->pMessage : "(no message)";
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    ++impl->validation_errors;
    if (impl->options.on_validation_error) {
      impl->options.on_validation_error(message);
    } else {
      log_error("Vulkan validation: " + message);
    }
  } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    log_warning("Vulkan validation: " + message);
  }
  return VK_FALSE;
}

bool has_layer(const char* name) {
  uint32_t n = 0;
  PENSIGHT_VK(vkEnumerateInstanceLayerProperties(&n, nullptr));
  std::vector<VkLayerProperties> layers(n);
  PENSIGHT_VK(vkEnumerateInstanceLayerProperties(&n, layers.data()));
  layers.resize(n);
  return std::any_of(layers.begin(), layers.end(), [&](const VkLayerProperties& l) {
    return std::strcmp(l.layerName, name) == 0;
  });
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  uint32_t n = 0;
  PENSIGHT_VK(vkEnumeratePhysicalDevices(instance, &n, nullptr));
  std::vector<VkPhysicalDevice> devices(n);
  PENSIGHT_VK(vkEnumeratePhysicalDevices(instance, &n, devices.data()));
  devices.resize(n);
  return devices;
}

VkInstance create_instance(bool validation, bool sync_validation, Context::Impl* impl,
                           VkDebugUtilsMessengerEXT* messenger) {
  init_loader();
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "pensight";
  app.pEngineName = "pensight";
  app.apiVersion = VK_API_VERSION_1_2;

  std::vector<const char*> layers, extensions;
  VkValidationFeatureEnableEXT enables[] = {
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  VkDebugUtilsMessengerCreateInfoEXT messenger_info{
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger_info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                   VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger_info.pfnUserCallback = on_debug_message;
  messenger_info.pUserData = impl;

  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  if (validation) {
    if (!has_layer("VK_LAYER_KHRONOS_validation")) {
      throw Error(
          "Vulkan validation was requested but VK_LAYER_KHRONOS_validation is not installed; "
          "install it with `apt-get install vulkan-validationlayers` or unset "
          "PENSIGHT_VK_VALIDATION");
    }
    layers.push_back("VK_LAYER_KHRONOS_validation");
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    features.enabledValidationFeatureCount = sync_validation ? 1 : 0;
    features.pEnabledValidationFeatures = enables;
    // Chain the messenger too, so instance creation and destruction are also checked.
    features.pNext = &messenger_info;
    ci.pNext = &features;
  }
  ci.enabledLayerCount = static_cast<uint32_t>(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  ci.ppEnabledExtensionNames = extensions.data();

  VkInstance instance = VK_NULL_HANDLE;
  const VkResult r = vkCreateInstance(&ci, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER) {
    throw Error(std::string("no Vulkan 1.2 driver found (vkCreateInstance: "
                            "VK_ERROR_INCOMPATIBLE_DRIVER). ") +
                kInstallHint);
  }
  check(r, "vkCreateInstance");
  // volk's instance-level pointers are process globals; core ones are loader trampolines valid
  // for every instance, but extension ones are not, so those are kept per instance (Impl).
  volkLoadInstanceOnly(instance);
  if (validation) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
    impl->destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    const VkResult mr = create && impl->destroy_messenger
                            ? create(instance, &messenger_info, nullptr, messenger)
                            : VK_ERROR_EXTENSION_NOT_PRESENT;
    if (mr != VK_SUCCESS) {
      vkDestroyInstance(instance, nullptr);
      check(mr, "vkCreateDebugUtilsMessengerEXT");
    }
  }
  return instance;
}

// The cache file is keyed by device and driver so a driver update never loads stale binaries
// (the driver would reject them anyway, but a mismatched file would be rewritten every run).
std::filesystem::path cache_file(const std::filesystem::path& dir, VkPhysicalDevice pd) {
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(pd, &p);
  std::ostringstream name;
  name << "vk-pipelines-" << std::hex << p.vendorID << "-" << p.deviceID << "-" << p.driverVersion
       << "-";
  for (uint8_t b : p.pipelineCacheUUID) name << (b >> 4) << (b & 15);
  name << ".bin";
  return dir / name.str();
}

std::string read_cache(const std::filesystem::path& path, VkPhysicalDevice pd) {
  const std::string data = read_file_bytes(path).value_or("");  // missing: a cold cache
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(pd, &p);
  VkPipelineCacheHeaderVersionOne header;
  if (data.size() < sizeof(header)) return {};
  std::memcpy(&header, data.data(), sizeof(header));
  if (header.headerVersion != VK_PIPELINE_CACHE_HEADER_VERSION_ONE ||
      header.vendorID != p.vendorID || header.deviceID != p.deviceID ||
      std::memcmp(header.pipelineCacheUUID, p.pipelineCacheUUID, VK_UUID_SIZE) != 0) {
    return {};
  }
  return data;
}

}  // namespace

const char* to_string(DeviceKind kind) {
  switch (kind) {
    case DeviceKind::kDiscrete:
      return "discrete GPU";
    case DeviceKind::kIntegrated:
      return "integrated GPU";
    case DeviceKind::kVirtual:
      return "virtual GPU";
    case DeviceKind::kCpu:
      return "CPU";
    case DeviceKind::kOther:
      return "other";
  }
  return "?";
}

std::vector<DeviceInfo> Context::list_devices() {
  Impl scratch;
  scratch.instance = create_instance(false, false, &scratch, nullptr);
  const auto devices = physical_devices(scratch.instance);
  std::vector<DeviceInfo> out;
  for (uint32_t i = 0; i < devices.size(); ++i) out.push_back(describe(devices[i], i));
  return out;
}

Context::Context(ContextOptions options) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  if (options.device.empty()) options.device = env_or("PENSIGHT_VK_DEVICE", "");
  if (!options.validation) options.validation = env_or("PENSIGHT_VK_VALIDATION", "0") == "1";
  if (options.cache_dir.empty()) options.cache_dir = cache_dir();
  d.options = options;

  d.instance = create_instance(options.validation, options.sync_validation, &d, &d.messenger);
  const std::vector<VkPhysicalDevice> devices = physical_devices(d.instance);
  std::vector<DeviceInfo> infos;
  for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(describe(devices[i], i));
  if (devices.empty()) {
    throw Error(std::string("the Vulkan loader found no device. ") + kInstallHint);
  }

  int chosen = -1;
  if (!options.device.empty()) {
    const std::string& want = options.device;
    if (std::all_of(want.begin(), want.end(), ::isdigit)) {
      const size_t i = std::stoul(want);
      if (i < infos.size()) chosen = static_cast<int>(i);
    } else {
      for (size_t i = 0; i < infos.size() && chosen < 0; ++i) {
        if (lower(infos[i].name).find(lower(want)) != std::string::npos)
          chosen = static_cast<int>(i);
      }
    }
    if (chosen < 0) {
      std::string names;
      for (const auto& info : infos)
        names += "\n  " + std::to_string(info.index) + ": " + info.name;
      throw Error("Vulkan device '" + want + "' (PENSIGHT_VK_DEVICE or --device) not found; " +
                  "available:" + names);
    }
  } else {
    for (size_t i = 0; i < infos.size(); ++i) {
      if (compute_queue_family(devices[i], nullptr) < 0) continue;
      if (chosen < 0 || preference(infos[i].kind) < preference(infos[chosen].kind)) {
        chosen = static_cast<int>(i);
      }
    }
    if (chosen < 0)
      throw Error(std::string("no Vulkan device has a compute queue. ") + kInstallHint);
  }
  d.physical = devices[chosen];
  d.info = infos[chosen];
  if (VK_API_VERSION_MINOR(d.info.api_version) < 2 &&
      VK_API_VERSION_MAJOR(d.info.api_version) == 1) {
    throw Error("Vulkan device '" + d.info.name + "' supports only Vulkan " +
                std::to_string(VK_API_VERSION_MAJOR(d.info.api_version)) + "." +
                std::to_string(VK_API_VERSION_MINOR(d.info.api_version)) +
                "; pensight needs 1.2. Update the driver (Mesa >= 21 for lavapipe).");
  }
  if (!d.info.subgroup_arithmetic) {
    throw Error("Vulkan device '" + d.info.name +
                "' lacks subgroup arithmetic in compute shaders, which pensight's reductions use; "
                "choose another device with PENSIGHT_VK_DEVICE or use --backend cpu");
  }
  const int family = compute_queue_family(d.physical, nullptr);
  if (family < 0) throw Error("Vulkan device '" + d.info.name + "' has no compute queue");
  d.queue_family = static_cast<uint32_t>(family);
  vkGetPhysicalDeviceMemoryProperties(d.physical, &d.memory);

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = d.queue_family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  f12.storageBuffer8BitAccess = d.info.int8_storage;
  VkPhysicalDeviceVulkan11Features f11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
  f11.storageBuffer16BitAccess = d.info.fp16_storage;
  f11.pNext = &f12;
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.pNext = &f11;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  PENSIGHT_VK(vkCreateDevice(d.physical, &dci, nullptr, &d.device));
  volkLoadDeviceTable(&d.vk, d.device);
  d.vk.vkGetDeviceQueue(d.device, d.queue_family, 0, &d.queue);

  std::string cache_data;
  if (options.cache_dir != "-" && !options.cache_dir.empty()) {
    d.cache_path = cache_file(options.cache_dir, d.physical);
    cache_data = read_cache(d.cache_path, d.physical);
  }
  VkPipelineCacheCreateInfo pcci{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
  pcci.initialDataSize = cache_data.size();
  pcci.pInitialData = cache_data.empty() ? nullptr : cache_data.data();
  PENSIGHT_VK(d.vk.vkCreatePipelineCache(d.device, &pcci, nullptr, &d.pipeline_cache));

  static std::mutex logged_mutex;
  static std::set<std::string> logged;
  std::lock_guard lock(logged_mutex);
  if (logged.insert(d.info.name + d.info.driver).second) {
    log_info("Vulkan device '" + d.info.name + "' (" + to_string(d.info.kind) + "), driver " +
             d.info.driver + (options.validation ? ", validation on" : ""));
  }
}

Context::~Context() {
  try {
    save_pipeline_cache();
  } catch (const std::exception& e) {
    log_warning(std::string("pipeline cache not saved: ") + e.what());
  }
}

// Runs also when the constructor throws half-way, so it must cope with any prefix of handles.
Context::Impl::~Impl() {
  // The registry's pipelines hold handles of this device: destroy them while it still exists.
  pipelines.entries.clear();
  if (device) {
    if (pipeline_cache) vk.vkDestroyPipelineCache(device, pipeline_cache, nullptr);
    vk.vkDestroyDevice(device, nullptr);
  }
  if (messenger) destroy_messenger(instance, messenger, nullptr);
  if (instance) vkDestroyInstance(instance, nullptr);
}

const DeviceInfo& Context::info() const {
  return impl_->info;
}
uint64_t Context::validation_errors() const {
  return impl_->validation_errors.load();
}
std::filesystem::path Context::pipeline_cache_path() const {
  return impl_->cache_path;
}

void Context::save_pipeline_cache() const {
  const Impl& d = *impl_;
  if (d.cache_path.empty() || !d.pipeline_cache) return;
  size_t size = 0;
  PENSIGHT_VK(d.vk.vkGetPipelineCacheData(d.device, d.pipeline_cache, &size, nullptr));
  std::vector<char> data(size);
  PENSIGHT_VK(d.vk.vkGetPipelineCacheData(d.device, d.pipeline_cache, &size, data.data()));
  write_cache_file(d.cache_path, std::string_view(data.data(), size));
}

uint32_t Context::Impl::memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                                    VkMemoryPropertyFlags preferred) const {
  int best = -1, best_score = -1;
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
    if (!(type_bits & (1u << i))) continue;
    const VkMemoryPropertyFlags f = memory.memoryTypes[i].propertyFlags;
    if ((f & required) != required) continue;
    const int score = __builtin_popcount(f & preferred);
    if (score > best_score) best = static_cast<int>(i), best_score = score;
  }
  if (best < 0) throw Error("Vulkan device '" + info.name + "' has no suitable memory type");
  return static_cast<uint32_t>(best);
}

void Context::Impl::submit_and_wait(VkCommandBuffer cmd, VkFence fence) const {
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  {
    std::lock_guard lock(queue_mutex);
    const int lose_after = options.lose_device_after_submits;
    if (lose_after > 0 && ++submits > lose_after) check(VK_ERROR_DEVICE_LOST, "vkQueueSubmit");
    PENSIGHT_VK(vk.vkQueueSubmit(queue, 1, &si, fence));
  }
  PENSIGHT_VK(vk.vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX));
}

}  // namespace pensight::vk
