// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// Softmax along one axis of [outer, len, inner], one invocation per (outer, inner) line.
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer X { STORE x[]; };
layout(std430, binding = 1) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push { uint outer, len, inner; };
#include "index.glsl"
void process(uint i) {
  uint base = (i / inner) * len * inner + i % inner;
  float mx = -3.402823466e38;
  for (uint k = 0; k < len; ++k) mx = max(mx, LD(x[base + k * inner]));
  float s = 0.0;
  for (uint k = 0; k < len; ++k) s += exp(LD(x[base + k * inner]) - mx);
  for (uint k = 0; k < len; ++k) y[base + k * inner] = ST(exp(LD(x[base + k * inner]) - mx) / s);
}

void main() {
  for (uint i = flat_index(); i < outer * inner; i += flat_stride()) process(i);
}
