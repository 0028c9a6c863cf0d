#version 450
#extension GL_GOOGLE_include_directive : require
// LayerNormalization over the trailing `inner` elements of each row (two-pass variance).
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer X { float x[]; };
layout(std430, binding = 1) readonly buffer S { float scale[]; };
layout(std430, binding = 2) readonly buffer B { float bias[]; };
layout(std430, binding = 3) writeonly buffer Y { float y[]; };
layout(push_constant) uniform Push {
  uint rows, inner;
  float eps;
};
#include "nn_index.glsl"
void process(uint r) {
  uint base = r * inner;
  float mean = 0.0;
  for (uint k = 0; k < inner; ++k) mean += x[base + k];
  mean /= float(inner);
  float var = 0.0;
  for (uint k = 0; k < inner; ++k) var += (x[base + k] - mean) * (x[base + k] - mean);
  float inv = inversesqrt(var / float(inner) + eps);
  for (uint k = 0; k < inner; ++k) y[base + k] = (x[base + k] - mean) * inv * scale[k] + bias[k];
}

void main() {
  for (uint r = flat_index(); r < rows; r += flat_stride()) process(r);
}
