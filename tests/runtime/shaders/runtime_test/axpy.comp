#version 450
// y = scale * a * x + y over n floats; the smallest kernel that lets runtime tests build dependent
// chains. SCALE (default 1) lets them tell pipelines with different specialization apart.
layout(local_size_x = 64) in;
layout(constant_id = 0) const float SCALE = 1.0;
layout(std430, binding = 0) readonly buffer X { float x[]; };
layout(std430, binding = 1) buffer Y { float y[]; };
layout(push_constant) uniform Push { float a; uint n; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < n) y[i] = SCALE * a * x[i] + y[i];
}
