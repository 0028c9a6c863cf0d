// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// Elementwise activation (ACT as in nn_act.glsl).
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint ACT = 1;
layout(constant_id = 1) const float ALPHA = 0.0;
layout(constant_id = 2) const float BETA = 0.0;
layout(std430, binding = 0) readonly buffer X { STORE x[]; };
layout(std430, binding = 1) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push { uint count; };
#include "act.glsl"
#include "index.glsl"
void main() {
  for (uint i = flat_index(); i < count; i += flat_stride()) y[i] = ST(activate(LD(x[i])));
}
