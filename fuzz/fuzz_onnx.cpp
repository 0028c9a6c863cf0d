// ONNX model import (import_onnx_bytes, as `pensight run --model` and the NN engine load them).
#include <string>

#include "fuzz/fuzz_input.h"
#include "kernels/nn/nn_onnx.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pensight::fuzz::quiet_log();
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  pensight::fuzz::expect_clean_error(
      [&] { pensight::kernels::import_onnx_bytes(bytes, "fuzz.onnx"); });
  return 0;
}
