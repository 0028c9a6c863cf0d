#pragma once
// Where a stage's kernels run: one vocabulary for every stage with more than one back-end (the FFT
// detector, dense depth, the renderer), on the command line, in the ROS parameters and in the
// Pipeline API. What kAuto resolves to on a device is runtime/device.h's choose_backend().
#include <string>

namespace pensight {

enum class Backend { kAuto, kCpu, kVulkan, kCuda };

const char* to_string(Backend backend);  // "auto" | "cpu" | "vulkan" | "cuda"
// The backend `name` names; throws pensight::Error listing the names for any other text.
Backend parse_backend(const std::string& name);

}  // namespace pensight
