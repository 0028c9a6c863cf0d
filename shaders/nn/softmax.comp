#version 450
#extension GL_GOOGLE_include_directive : require
// Softmax along one axis of [outer, len, inner], one invocation per (outer, inner) line.
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer X { float x[]; };
layout(std430, binding = 1) writeonly buffer Y { float y[]; };
layout(push_constant) uniform Push { uint outer, len, inner; };
#include "nn_index.glsl"
void process(uint i) {
  uint base = (i / inner) * len * inner + i % inner;
  float mx = -3.402823466e38;
  for (uint k = 0; k < len; ++k) mx = max(mx, x[base + k * inner]);
  float s = 0.0;
  for (uint k = 0; k < len; ++k) s += exp(x[base + k * inner] - mx);
  for (uint k = 0; k < len; ++k) y[base + k * inner] = exp(x[base + k * inner] - mx) / s;
}

void main() {
  for (uint i = flat_index(); i < outer * inner; i += flat_stride()) process(i);
}
