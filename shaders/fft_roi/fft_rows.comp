#version 450
#extension GL_GOOGLE_include_directive : require
// Row pass of the real 2D FFT: each workgroup transforms two real rows of one ROI as one complex
// FFT (z = a + i b) and separates them by Hermitian symmetry, writing bins 0..FFT_N/2 of both.

layout(local_size_x_id = 1) in;  // FFT_N / 2
layout(constant_id = 0) const uint FFT_N = 256;

layout(std430, binding = 0) readonly buffer Samples { float samples[]; };
layout(std430, binding = 1) writeonly buffer Spectrum { vec2 spectrum[]; };
layout(push_constant) uniform Push { uint num_rois; };

#include "fft_radix2.glsl"

vec2 result(bool in_x, uint k) { return in_x ? fft_x[k] : fft_y[k]; }

void main() {
  uint roi = gl_WorkGroupID.y;
  if (roi >= num_rois) return;  // uniform across the workgroup
  uint i = gl_LocalInvocationID.x;
  const uint half_n = FFT_N / 2u;
  const uint w = half_n + 1u;
  uint row = 2u * gl_WorkGroupID.x;
  uint src = (roi * FFT_N + row) * FFT_N;
  fft_x[i] = vec2(samples[src + i], samples[src + FFT_N + i]);
  fft_x[i + half_n] = vec2(samples[src + i + half_n], samples[src + FFT_N + i + half_n]);
  bool in_x = fft_forward();

  uint dst = (roi * FFT_N + row) * w;
  for (uint k = i; k <= half_n; k += half_n) {
    vec2 zk = result(in_x, k);
    vec2 zc = result(in_x, (FFT_N - k) & (FFT_N - 1u));
    zc.y = -zc.y;
    vec2 d = zk - zc;
    spectrum[dst + k] = 0.5 * (zk + zc);      // row a
    spectrum[dst + w + k] = 0.5 * vec2(d.y, -d.x);  // row b = (zk - conj(z[-k])) / 2i
    if (i != 0u) break;  // only invocation 0 also writes the Nyquist bin k = FFT_N / 2
  }
}
