#include <gtest/gtest.h>

#include "core/error.h"
#include "runtime/cuda_device.h"

namespace pensight {
namespace {

TEST(Cuda, DeviceInfoOrClearError) {
  if (!cuda::available()) {
    EXPECT_THROW(cuda::device_info(), Error);
    GTEST_SKIP() << "no CUDA device (or built without CUDA)";
  }
  const cuda::DeviceInfo info = cuda::device_info();
  EXPECT_FALSE(info.name.empty());
  EXPECT_GT(info.memory_bytes, 0u);
}

}  // namespace
}  // namespace pensight
