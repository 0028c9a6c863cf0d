#pragma once
// Internal to CUDA implementation files: error checks and an owning device array.
#include <cuda_runtime.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"

namespace pensight::cuda {

inline void check(cudaError_t e, const char* call) {
  // Sticky errors: the CUDA context is unusable until the process restarts.
  switch (e) {
    case cudaErrorIllegalAddress:
    case cudaErrorLaunchFailure:
    case cudaErrorLaunchTimeout:
    case cudaErrorHardwareStackError:
    case cudaErrorIllegalInstruction:
    case cudaErrorMisalignedAddress:
    case cudaErrorInvalidPc:
    case cudaErrorECCUncorrectable:
      throw DeviceLostError(std::string(call) + " failed: " + cudaGetErrorName(e) +
                            " (the CUDA context is lost); restart the program, or run on the CPU "
                            "(--backend cpu)");
    default:
      break;
  }
  if (e != cudaSuccess) {
    throw Error(std::string(call) + " failed: " + cudaGetErrorName(e) + " (" +
                cudaGetErrorString(e) + ")");
  }
}
#define PENSIGHT_CUDA(call) ::pensight::cuda::check((call), #call)

// Device memory for `count` elements of T, freed on destruction.
template <class T>
class DeviceArray {
 public:
  explicit DeviceArray(size_t count) : count_(count) {
    PENSIGHT_CUDA(cudaMalloc(&data_, (count ? count : 1) * sizeof(T)));
  }
  ~DeviceArray() { cudaFree(data_); }
  DeviceArray(DeviceArray&& o) noexcept
      : data_(std::exchange(o.data_, nullptr)), count_(std::exchange(o.count_, 0)) {}
  DeviceArray& operator=(DeviceArray&& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(count_, o.count_);
    return *this;
  }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;

  T* data() { return data_; }
  const T* data() const { return data_; }
  size_t size() const { return count_; }
  void upload(const T* src, size_t n, cudaStream_t stream = nullptr) {
    PENSIGHT_CUDA(cudaMemcpyAsync(data_, src, n * sizeof(T), cudaMemcpyHostToDevice, stream));
  }
  void download(T* dst, size_t n, cudaStream_t stream = nullptr) const {
    PENSIGHT_CUDA(cudaMemcpyAsync(dst, data_, n * sizeof(T), cudaMemcpyDeviceToHost, stream));
  }
  // All elements, after the work queued on the default stream has finished.
  std::vector<T> to_vector() const {
    std::vector<T> out(count_);
    download(out.data(), count_);
    PENSIGHT_CUDA(cudaDeviceSynchronize());
    return out;
  }

 private:
  T* data_ = nullptr;
  size_t count_ = 0;
};

}  // namespace pensight::cuda
