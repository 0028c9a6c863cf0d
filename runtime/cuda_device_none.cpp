// Built when PENSIGHT_CUDA is off, so callers need no #ifdefs.
#include "core/error.h"
#include "runtime/cuda_device.h"

namespace pensight::cuda {

bool available() {
  return false;
}

DeviceInfo device_info() {
  throw Error(
      "pensight was built without CUDA (configure with -DPENSIGHT_CUDA=ON where nvcc exists)");
}

}  // namespace pensight::cuda
