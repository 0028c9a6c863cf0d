// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// Broadcasting binary op over a 4-D output; the inputs' strides are 0 along broadcast axes.
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint OP = 0;  // 0 add, 1 sub, 2 mul, 3 div, 4 pow
layout(std430, binding = 0) readonly buffer A { STORE a[]; };
layout(std430, binding = 1) readonly buffer B { STORE b[]; };
layout(std430, binding = 2) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push {
  uvec4 shape;
  uvec4 sa;
  uvec4 sb;
  uint count;
};
#include "index.glsl"
void process(uint i) {
  uint d3 = i % shape.w, t = i / shape.w;
  uint d2 = t % shape.z;
  t /= shape.z;
  uint d1 = t % shape.y, d0 = t / shape.y;
  uvec4 d = uvec4(d0, d1, d2, d3);
  float p = LD(a[d.x * sa.x + d.y * sa.y + d.z * sa.z + d.w * sa.w]);
  float q = LD(b[d.x * sb.x + d.y * sb.y + d.z * sb.z + d.w * sb.w]);
  float r;
  if (OP == 0) r = p + q;
  else if (OP == 1) r = p - q;
  else if (OP == 2) r = p * q;
  else if (OP == 3) r = p / q;
  else r = q == 2.0 ? p * p : pow(p, q);
  y[i] = ST(r);
}

void main() {
  for (uint i = flat_index(); i < count; i += flat_stride()) process(i);
}
