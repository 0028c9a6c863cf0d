#version 450
#extension GL_GOOGLE_include_directive : require
// Column pass of the real 2D FFT, in place: each workgroup transforms one column kx of one ROI's
// half spectrum (FFT_N / 2 + 1 columns, row-major rows of FFT_N / 2 + 1 bins).

layout(local_size_x_id = 1) in;  // FFT_N / 2
layout(constant_id = 0) const uint FFT_N = 256;

layout(std430, binding = 0) buffer Spectrum { vec2 spectrum[]; };
layout(push_constant) uniform Push { uint num_rois; };

#include "fft_radix2.glsl"

void main() {
  uint roi = gl_WorkGroupID.y;
  if (roi >= num_rois) return;  // uniform across the workgroup
  uint i = gl_LocalInvocationID.x;
  const uint half_n = FFT_N / 2u;
  const uint w = half_n + 1u;
  uint base = roi * FFT_N * w + gl_WorkGroupID.x;
  fft_x[i] = spectrum[base + i * w];
  fft_x[i + half_n] = spectrum[base + (i + half_n) * w];
  bool in_x = fft_forward();
  spectrum[base + i * w] = in_x ? fft_x[i] : fft_y[i];
  spectrum[base + (i + half_n) * w] = in_x ? fft_x[i + half_n] : fft_y[i + half_n];
}
