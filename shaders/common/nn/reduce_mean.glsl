// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// Mean over the axes where keep[i] == 1 and in[i] > 1 (4-D), one invocation per output element.
// Also GlobalAveragePool (keep = [N, C, 1, 1]).
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer X { STORE x[]; };
layout(std430, binding = 1) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push {
  uvec4 keep;
  uvec4 shape;
  uint count;
};
#include "index.glsl"
void process(uint i) {
  uint k3 = i % keep.w, t = i / keep.w;
  uint k2 = t % keep.z;
  t /= keep.z;
  uint k1 = t % keep.y, k0 = t / keep.y;
  uvec4 r = uvec4(keep.x == 1 ? shape.x : 1, keep.y == 1 ? shape.y : 1,
                  keep.z == 1 ? shape.z : 1, keep.w == 1 ? shape.w : 1);
  uvec4 st = uvec4(shape.y * shape.z * shape.w, shape.z * shape.w, shape.w, 1);
  float acc = 0.0;
  for (uint a = 0; a < r.x; ++a)
    for (uint b = 0; b < r.y; ++b)
      for (uint c = 0; c < r.z; ++c) {
        uint base = (k0 + a) * st.x + (k1 + b) * st.y + (k2 + c) * st.z + k3;
        for (uint d = 0; d < r.w; ++d) acc += LD(x[base + d]);
      }
  y[i] = ST(acc / float(r.x * r.y * r.z * r.w));
}

void main() {
  for (uint i = flat_index(); i < count; i += flat_stride()) process(i);
}
