#pragma once
// The CUDA side of the runtime: whether a CUDA device can be used, and which one. Kernel CUDA
// implementations (kernels/*/*_cuda.cu) use runtime/cuda_check.cuh for errors and memory.
#include <cstddef>
#include <string>

namespace pensight::cuda {

struct DeviceInfo {
  std::string name;
  int compute_major = 0;
  int compute_minor = 0;
  size_t memory_bytes = 0;
};

// True when pensight was built with CUDA (PENSIGHT_HAS_CUDA) and a CUDA device is present.
bool available();
// Device 0; throws pensight::Error saying why when !available().
DeviceInfo device_info();

}  // namespace pensight::cuda
