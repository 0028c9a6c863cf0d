#include "core/backend.h"

#include "core/error.h"

namespace pensight {

const char* to_string(Backend backend) {
  switch (backend) {
    case Backend::kAuto:
      return "auto";
    case Backend::kCpu:
      return "cpu";
    case Backend::kVulkan:
      return "vulkan";
    case Backend::kCuda:
      return "cuda";
  }
  return "unknown";
}

Backend parse_backend(const std::string& name) {
  for (Backend b : {Backend::kAuto, Backend::kCpu, Backend::kVulkan, Backend::kCuda}) {
    if (name == to_string(b)) return b;
  }
  throw Error("unknown backend '" + name + "'; use auto, cpu, vulkan or cuda");
}

}  // namespace pensight
