#version 450
#extension GL_GOOGLE_include_directive : require
// One workgroup per ROI: mean, then variance (two passes, to avoid E[x^2]-E[x]^2 cancellation),
// then the normalised pixels. Pixels are shifted by the ROI's first pixel before summing so a
// flat ROI gives exactly zero variance in float, matching the CPU reference's flat rule.

layout(local_size_x = 256) in;
layout(constant_id = 0) const uint WIDTH = 720;
layout(constant_id = 1) const uint HEIGHT = 540;
layout(constant_id = 2) const uint BITS = 8;
layout(constant_id = 3) const uint ROI = 300;

layout(std430, binding = 0) readonly buffer ImageWords { uint words[]; };
layout(std430, binding = 1) readonly buffer Origins { ivec2 origins[]; };
layout(std430, binding = 2) writeonly buffer Out { float values[]; };
layout(push_constant) uniform Push { uint num_rois; };

#include "pixels.glsl"
#include "reduce.glsl"
PENSIGHT_DEFINE_WORKGROUP_SUM(256)

const float kFlatVariance = 1e-9;

void main() {
  uint roi = gl_WorkGroupID.x;
  if (roi >= num_rois) return;  // uniform across the workgroup
  uvec2 o = uvec2(origins[roi]);
  uint n = ROI * ROI;
  float ref = load_pixel(o.x, o.y);

  float s = 0.0;
  for (uint i = gl_LocalInvocationID.x; i < n; i += 256u) {
    s += load_pixel(o.x + i % ROI, o.y + i / ROI) - ref;
  }
  float mean = workgroup_sum(s) / float(n);

  float q = 0.0;
  for (uint i = gl_LocalInvocationID.x; i < n; i += 256u) {
    float d = load_pixel(o.x + i % ROI, o.y + i / ROI) - ref - mean;
    q += d * d;
  }
  float var = workgroup_sum(q) / float(n);
  float inv_std = var > kFlatVariance ? inversesqrt(var) : 0.0;

  uint base = roi * n;
  for (uint i = gl_LocalInvocationID.x; i < n; i += 256u) {
    values[base + i] = (load_pixel(o.x + i % ROI, o.y + i / ROI) - ref - mean) * inv_std;
  }
}
