// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// Mean over the axes where keep[i] == 1 and in[i] > 1 (4-D); also GlobalAveragePool (keep =
// [N, C, 1, 1]). One workgroup per output element (grid-stride over the outputs): its 256
// invocations stride over the reduced elements, then a shared-memory tree sums their partials.
// A reduction of any size then takes at most size / 256 iterations per invocation: llvmpipe stops
// a loop after 65535 iterations (LP_MAX_TGSI_LOOP_ITERATIONS), which a single invocation summing a
// 320x240 plane would pass, and a GPU keeps all lanes busy.
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer X { STORE x[]; };
layout(std430, binding = 1) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push {
  uvec4 keep;
  uvec4 shape;
  uint count;
};
shared float partial[256];

void main() {
  const uint lid = gl_LocalInvocationID.x;
  const uvec4 r = uvec4(keep.x == 1 ? shape.x : 1, keep.y == 1 ? shape.y : 1,
                        keep.z == 1 ? shape.z : 1, keep.w == 1 ? shape.w : 1);
  const uvec4 st = uvec4(shape.y * shape.z * shape.w, shape.z * shape.w, shape.w, 1);
  const uint reduced = r.x * r.y * r.z * r.w;
  const uint groups = gl_NumWorkGroups.x * gl_NumWorkGroups.y;
  // The bound is the same for the whole workgroup, so every barrier below is reached by all.
  for (uint i = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; i < count; i += groups) {
    uint k3 = i % keep.w, t = i / keep.w;
    uint k2 = t % keep.z;
    t /= keep.z;
    uint k1 = t % keep.y, k0 = t / keep.y;
    float acc = 0.0;
    for (uint j = lid; j < reduced; j += 256u) {
      uint d = j % r.w, u = j / r.w;
      uint c = u % r.z;
      u /= r.z;
      uint b = u % r.y, a = u / r.y;
      acc += LD(x[(k0 + a) * st.x + (k1 + b) * st.y + (k2 + c) * st.z + k3 + d]);
    }
    partial[lid] = acc;
    barrier();
    for (uint half_n = 128u; half_n > 0u; half_n >>= 1) {
      if (lid < half_n) partial[lid] += partial[lid + half_n];
      barrier();
    }
    if (lid == 0u) y[i] = ST(partial[0] / float(reduced));
    barrier();  // partial[0] is read before the next output overwrites it
  }
}
