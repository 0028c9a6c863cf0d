#include "runtime/cuda_check.cuh"
#include "runtime/cuda_device.h"

namespace pensight::cuda {

bool available() {
  int count = 0;
  return cudaGetDeviceCount(&count) == cudaSuccess && count > 0;
}

DeviceInfo device_info() {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess || count == 0) {
    throw Error(std::string("no CUDA device: ") +
                (e != cudaSuccess ? cudaGetErrorString(e) : "cudaGetDeviceCount returned 0") +
                " (install the NVIDIA driver, or use --backend vulkan|cpu)");
  }
  cudaDeviceProp p{};
  PENSIGHT_CUDA(cudaGetDeviceProperties(&p, 0));
  return {p.name, p.major, p.minor, p.totalGlobalMem};
}

}  // namespace pensight::cuda
