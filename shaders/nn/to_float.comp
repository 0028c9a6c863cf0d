#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_16bit_storage : require
// fp16-storage models: converts a graph input (fp32) in, or a graph output (fp32) out.
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer S { float16_t src[]; };
layout(std430, binding = 1) writeonly buffer D { float dst[]; };
layout(push_constant) uniform Push { uint count; };
#include "nn/index.glsl"
void main() {
  for (uint i = flat_index(); i < count; i += flat_stride()) dst[i] = float(src[i]);
}
