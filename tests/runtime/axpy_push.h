#pragma once
// The push constants of tests/runtime/shaders/runtime_test/axpy.comp (y = SCALE * a * x + y over n
// floats), the test shader of the runtime's own tests.
#include <cstdint>

namespace pensight::testing {

struct AxpyPush {
  float a;
  uint32_t n;
};

}  // namespace pensight::testing
