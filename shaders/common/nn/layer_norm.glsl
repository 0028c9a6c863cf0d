// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// LayerNormalization over the trailing `inner` elements of each row (two-pass variance).
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer X { STORE x[]; };
layout(std430, binding = 1) readonly buffer S { STORE scale[]; };
layout(std430, binding = 2) readonly buffer B { STORE bias[]; };
layout(std430, binding = 3) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push {
  uint rows, inner;
  float eps;
};
#include "index.glsl"
void process(uint r) {
  uint base = r * inner;
  float mean = 0.0;
  for (uint k = 0; k < inner; ++k) mean += LD(x[base + k]);
  mean /= float(inner);
  float var = 0.0;
  for (uint k = 0; k < inner; ++k) var += (LD(x[base + k]) - mean) * (LD(x[base + k]) - mean);
  float inv = inversesqrt(var / float(inner) + eps);
  for (uint k = 0; k < inner; ++k) y[base + k] = ST((LD(x[base + k]) - mean) * inv * LD(scale[k]) + LD(bias[k]));
}

void main() {
  for (uint r = flat_index(); r < rows; r += flat_stride()) process(r);
}
