#pragma once
// Errors thrown by pensight. Messages name the thing that failed and, where there is one, the fix.
#include <stdexcept>
#include <string>

namespace pensight {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A Vulkan call returned an error; what() names the call and the VkResult.
class VulkanError : public Error {
 public:
  VulkanError(const std::string& call, int result);
  int result() const { return result_; }

 private:
  int result_ = 0;
};

// The GPU stopped answering (Vulkan VK_ERROR_DEVICE_LOST, a sticky CUDA error): nothing more runs
// on it in this process, so a pipeline that meets it ends the run instead of going on frame by
// frame. what() names the call and the way out.
class DeviceLostError : public Error {
 public:
  using Error::Error;
};

}  // namespace pensight
