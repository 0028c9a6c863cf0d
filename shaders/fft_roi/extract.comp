#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// One workgroup per ROI: prefiltered bilinear resample of the ROI to FFT_N^2 samples, zero mean / unit
// variance, separable Hann window, and the local-contrast energy centroid (RoiLattice fields 6, 7;
// the peaks pass writes fields 0..5). Mirrors FftRoiCpu's prepare step (kernels/fft_roi).

layout(local_size_x = 256) in;
layout(constant_id = 0) const uint WIDTH = 720;
layout(constant_id = 1) const uint ROI = 300;
layout(constant_id = 2) const uint FFT_N = 256;
layout(constant_id = 3) const uint WINDOW = 1;
const uint BITS = 8;

layout(std430, binding = 0) readonly buffer ImageWords { uint words[]; };
layout(std430, binding = 1) readonly buffer Origins { ivec2 origins[]; };
layout(std430, binding = 2) coherent buffer Samples { float samples[]; };
layout(std430, binding = 3) writeonly buffer Lattices { float lattices[]; };  // 8 floats per ROI
layout(push_constant) uniform Push { uint num_rois; };

#include "pixels.glsl"
#include "reduce.glsl"
PENSIGHT_DEFINE_WORKGROUP_SUM(256)

const float kFlatVariance = 1e-9;
const float kPi = 3.14159265358979323846;

// Resampling taps of index u: [1 2 1]/4 binomial convolved with linear interpolation, source
// indices floor(x) - 1 .. floor(x) + 2 clamped to the ROI (see Taps in fft_roi_cpu.cpp for why).
void taps(uint u, out uint index[4], out float weight[4]) {
  float x = (float(u) + 0.5) * (float(ROI) / float(FFT_N)) - 0.5;
  float fl = floor(x);
  float f = x - fl;
  int i = int(fl);
  for (int j = 0; j < 4; ++j) index[j] = uint(clamp(i - 1 + j, 0, int(ROI) - 1));
  weight[0] = (1.0 - f) / 4.0;
  weight[1] = (2.0 - f) / 4.0;
  weight[2] = (1.0 + f) / 4.0;
  weight[3] = f / 4.0;
}

float window_of(uint u) {
  if (WINDOW == 0u) return 1.0;
  float s = sin(kPi * (float(u) + 0.5) / float(FFT_N));
  return s * s;
}

// Window and taps per index, computed once per workgroup (rows and columns share them).
shared float s_window[FFT_N];
shared uvec4 s_index[FFT_N];
shared vec4 s_weight[FFT_N];

float window(uint u) { return s_window[u]; }

float resample(uvec2 o, uint u, uint v) {
  if (FFT_N == ROI) return load_pixel(o.x + u, o.y + v);
  uvec4 ix = s_index[u], iy = s_index[v];
  vec4 wx = s_weight[u], wy = s_weight[v];
  float result = 0.0;
  for (int j = 0; j < 4; ++j) {
    float row = 0.0;
    for (int i = 0; i < 4; ++i) row += wx[i] * load_pixel(o.x + ix[i], o.y + iy[j]);
    result += wy[j] * row;
  }
  return result;
}

void main() {
  uint roi = gl_WorkGroupID.x;
  if (roi >= num_rois) return;  // uniform across the workgroup
  uvec2 o = uvec2(origins[roi]);
  uint n = FFT_N * FFT_N;
  uint base = roi * n;
  for (uint u = gl_LocalInvocationID.x; u < FFT_N; u += 256u) {
    uint index[4];
    float weight[4];
    taps(u, index, weight);
    s_index[u] = uvec4(index[0], index[1], index[2], index[3]);
    s_weight[u] = vec4(weight[0], weight[1], weight[2], weight[3]);
    s_window[u] = window_of(u);
  }
  barrier();

  // Each invocation re-reads only what it wrote itself, so no barrier is needed between loops.
  float s = 0.0;
  for (uint i = gl_LocalInvocationID.x; i < n; i += 256u) {
    float v = resample(o, i % FFT_N, i / FFT_N);
    samples[base + i] = v;
    s += v;
  }
  float mean = workgroup_sum(s) / float(n);
  float q = 0.0;
  for (uint i = gl_LocalInvocationID.x; i < n; i += 256u) {
    float d = samples[base + i] - mean;
    q += d * d;
  }
  float var = workgroup_sum(q) / float(n);
  float inv_std = var > kFlatVariance ? inversesqrt(var) : 0.0;
  // The last pass goes block by block (16 x 16 blocks, one per invocation) for the centroid of
  // local contrast energy: each block's variance about its own mean, at the block centre. The
  // samples were written by other invocations: make them visible first.
  memoryBarrierBuffer();
  barrier();
  uint bx = gl_LocalInvocationID.x % 16u, by = gl_LocalInvocationID.x / 16u;
  uint u0 = bx * FFT_N / 16u, u1 = (bx + 1u) * FFT_N / 16u;
  uint v0 = by * FFT_N / 16u, v1 = (by + 1u) * FFT_N / 16u;
  float sum = 0.0, sq = 0.0;
  for (uint v = v0; v < v1; ++v) {
    for (uint u = u0; u < u1; ++u) {
      uint i = v * FFT_N + u;
      float x = (samples[base + i] - mean) * (window(v) * inv_std * window(u));
      samples[base + i] = x;
      sum += x;
      sq += x * x;
    }
  }
  float e = max(0.0, sq - sum * sum / float((v1 - v0) * (u1 - u0)));
  float eu = e * 0.5 * float(u0 + u1 - 1u);
  float ev = e * 0.5 * float(v0 + v1 - 1u);
  e = workgroup_sum(e);
  eu = workgroup_sum(eu);
  ev = workgroup_sum(ev);
  if (gl_LocalInvocationID.x == 0u) {
    float centre = 0.5 * float(FFT_N - 1u), scale = float(ROI) / float(FFT_N);
    lattices[roi * 8u + 6u] = e > 0.0 ? (eu / e - centre) * scale : 0.0;
    lattices[roi * 8u + 7u] = e > 0.0 ? (ev / e - centre) * scale : 0.0;
  }
}
