// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// dst[dst_off + d . dst_stride] = src[src_off + d . src_stride] over a 4-D index space: Concat
// (one dispatch per input), Transpose and Slice.
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer S { STORE src[]; };
layout(std430, binding = 1) buffer D { STORE dst[]; };
layout(push_constant) uniform Push {
  uvec4 shape;
  uvec4 ss;
  uvec4 ds;
  uint src_off;
  uint dst_off;
  uint count;
};
#include "index.glsl"
void process(uint i) {
  uint d3 = i % shape.w, t = i / shape.w;
  uint d2 = t % shape.z;
  t /= shape.z;
  uint d1 = t % shape.y, d0 = t / shape.y;
  uvec4 d = uvec4(d0, d1, d2, d3);
  dst[dst_off + d.x * ds.x + d.y * ds.y + d.z * ds.z + d.w * ds.w] =
      src[src_off + d.x * ss.x + d.y * ss.y + d.z * ss.z + d.w * ss.w];
}

void main() {
  for (uint i = flat_index(); i < count; i += flat_stride()) process(i);
}
