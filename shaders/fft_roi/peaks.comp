#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// One workgroup per ROI: the two base frequency vectors of the net lattice from the ROI's half
// spectrum. Mirrors analyze_spectrum() in kernels/fft_roi/fft_roi_peaks.cpp step by step: same
// band, same tie-break (first bin in row-major order), same beyond-band, sub-harmonic,
// below-band and sub-bin rules.

layout(local_size_x = 256) in;
layout(constant_id = 0) const uint FFT_N = 256;
layout(constant_id = 1) const uint ROI = 300;
layout(constant_id = 2) const float R2_MIN = 9.0;        // band, squared radius in bins
layout(constant_id = 3) const float R2_MAX = 13271.04;
layout(constant_id = 4) const float COS2_MAX = 0.8214;   // cos^2 of the minimum angle
layout(constant_id = 5) const float SUBHARMONIC = 0.2;
layout(constant_id = 6) const uint SUBBIN = 1;
layout(constant_id = 7) const float BEYOND_BAND = 1.0;  // PeakParams::beyond_band_ratio
layout(constant_id = 8) const float BELOW_BAND = 0.5;   // PeakParams::below_band_ratio
layout(constant_id = 9) const int MIN_COARSE_R2 = 4;    // kMinCoarseCycles squared
layout(constant_id = 10) const int MIN_COARSE = 2;      // kMinCoarseCycles
layout(constant_id = 11) const float RIDGE_PROMINENCE = 4.0;  // kRidgeProminence
layout(constant_id = 12) const int RIDGE_OFFSET0 = 4;   // kRidgeOffset0, kRidgeOffset1
layout(constant_id = 13) const int RIDGE_OFFSET1 = 5;

layout(std430, binding = 0) readonly buffer Spectrum { vec2 spectrum[]; };
layout(std430, binding = 1) writeonly buffer Lattices { float lattices[]; };  // 8 floats per ROI
layout(push_constant) uniform Push { uint num_rois; };

#include "reduce.glsl"
PENSIGHT_DEFINE_WORKGROUP_SUM(256)

const uint W = FFT_N / 2u + 1u;
shared float best_power[256];
shared uint best_index[256];
uint base;

float power(int kx, int ky) {
  if (kx < 0) {
    kx = -kx;
    ky = -ky;
  }
  uint row = uint(ky & int(FFT_N - 1u));
  vec2 c = spectrum[base + row * W + uint(kx)];
  return c.x * c.x + c.y * c.y;
}

bool in_band(int kx, int ky) {
  if (kx == 0 && ky <= 0) return false;
  float r2 = float(kx * kx + ky * ky);
  return r2 >= R2_MIN && r2 <= R2_MAX;
}

// Between the band and the Nyquist circle.
bool beyond_band(int kx, int ky) {
  if (kx == 0 && ky <= 0) return false;
  float r2 = float(kx * kx + ky * ky);
  return r2 > R2_MAX && r2 <= float((FFT_N / 2u) * (FFT_N / 2u));
}

ivec2 bin_of(uint index) {
  uint row = index / W;
  int ky = row < FFT_N / 2u ? int(row) : int(row) - int(FFT_N);
  return ivec2(int(index % W), ky);
}

// Workgroup argmax; ties go to the lower index. Every invocation receives the winner's index
// (0xffffffff when no invocation had a candidate).
uint workgroup_argmax(float v, uint index) {
  uint lid = gl_LocalInvocationID.x;
  best_power[lid] = v;
  best_index[lid] = index;
  barrier();
  for (uint s = 128u; s > 0u; s >>= 1u) {
    if (lid < s) {
      float a = best_power[lid], b = best_power[lid + s];
      if (b > a || (b == a && best_index[lid + s] < best_index[lid])) {
        best_power[lid] = b;
        best_index[lid] = best_index[lid + s];
      }
    }
    barrier();
  }
  uint winner = best_power[0] > 0.0 ? best_index[0] : 0xffffffffu;
  barrier();
  return winner;
}

// radial_floor() in fft_roi_peaks.cpp: the strongest bin RIDGE_OFFSET0/1 bins (along the larger
// axis) further out and nearer in on the line through DC and b.
float radial_floor(ivec2 b) {
  int ax = abs(b.x), ay = abs(b.y), r = max(ax, ay);
  int sx = b.x < 0 ? -1 : 1, sy = b.y < 0 ? -1 : 1;
  float floor_v = 0.0;
  for (int k = 0; k < 2; ++k) {
    int offset = k == 0 ? RIDGE_OFFSET0 : RIDGE_OFFSET1;
    for (int side = -1; side <= 1; side += 2) {
      int m = r + side * offset;
      if (m < MIN_COARSE) continue;
      int x = (2 * ax * m + r) / (2 * r), y = (2 * ay * m + r) / (2 * r);
      floor_v = max(floor_v, power(sx * x, sy * y));
    }
  }
  return floor_v;
}

ivec2 fundamental(ivec2 p) {
  float pp = power(p.x, p.y);
  int hx = int(floor(float(p.x) * 0.5 + 0.5));
  int hy = int(floor(float(p.y) * 0.5 + 0.5));
  if (float(hx * hx + hy * hy) < R2_MIN) return p;
  ivec2 best = ivec2(0);
  float best_v = -1.0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      float v = power(hx + dx, hy + dy);
      if (v > best_v) {
        best_v = v;
        best = ivec2(hx + dx, hy + dy);
      }
    }
  }
  if (!(best_v >= SUBHARMONIC * pp)) return p;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (power(best.x + dx, best.y + dy) > best_v) return p;
  if (!(best_v >= RIDGE_PROMINENCE * radial_floor(best))) return p;
  if (best.x < 0 || (best.x == 0 && best.y < 0)) best = -best;
  return best;
}

// The lattice at p is the second harmonic of a coarser one below the band (coarser_than_band()).
bool coarser_than_band(ivec2 p) {
  float pp = power(p.x, p.y);
  ivec2 best = ivec2(0);
  float best_v = -1.0;
  for (int y2 = p.y - 1; y2 <= p.y + 1; ++y2) {
    for (int x2 = p.x - 1; x2 <= p.x + 1; ++x2) {
      // Bit tests and shifts: GLSL leaves % and / of negative integers undefined.
      if (((y2 | x2) & 1) != 0) continue;
      float v = power(x2 >> 1, y2 >> 1);
      if (v > best_v) {
        best_v = v;
        best = ivec2(x2 >> 1, y2 >> 1);
      }
    }
  }
  int r2 = best.x * best.x + best.y * best.y;
  if (float(r2) >= R2_MIN || r2 < MIN_COARSE_R2 || !(best_v >= BELOW_BAND * pp)) return false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (power(best.x + dx, best.y + dy) > best_v) return false;
  return true;
}

float log_power(float p) { return log(max(p, 1e-30)); }

float vertex(float lm, float l0, float lp) {
  float denom = lm - 2.0 * l0 + lp;
  if (!(denom < 0.0)) return 0.0;
  return clamp(0.5 * (lm - lp) / denom, -0.5, 0.5);
}

vec2 refine(ivec2 b) {
  vec2 d = vec2(0.0);
  if (SUBBIN != 0u) {
    float l0 = log_power(power(b.x, b.y));
    d.x = vertex(log_power(power(b.x - 1, b.y)), l0, log_power(power(b.x + 1, b.y)));
    d.y = vertex(log_power(power(b.x, b.y - 1)), l0, log_power(power(b.x, b.y + 1)));
  }
  vec2 f = (vec2(b) + d) / float(ROI);
  // A peak on the kx = 0 column may refine to kx < 0: back to the half plane.
  return (f.x < 0.0 || (f.x == 0.0 && f.y < 0.0)) ? -f : f;
}

float energy3x3(ivec2 b) {
  float e = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) e += power(b.x + dx, b.y + dy);
  return e;
}

void main() {
  uint roi = gl_WorkGroupID.x;
  if (roi >= num_rois) return;  // uniform across the workgroup
  base = roi * FFT_N * W;
  uint lid = gl_LocalInvocationID.x;
  uint total = FFT_N * W;

  float energy = 0.0, count = 0.0, v1 = -1.0, vb = -1.0;
  uint i1 = 0u, ib = 0u;
  for (uint i = lid; i < total; i += 256u) {
    ivec2 k = bin_of(i);
    if (!in_band(k.x, k.y)) {
      if (beyond_band(k.x, k.y)) {
        float v = power(k.x, k.y);
        if (v > vb) {
          vb = v;
          ib = i;
        }
      }
      continue;
    }
    float v = power(k.x, k.y);
    energy += v;
    count += 1.0;
    if (v > v1) {
      v1 = v;
      i1 = i;
    }
  }
  energy = workgroup_sum(energy);
  count = workgroup_sum(count);
  uint w1 = workgroup_argmax(v1, i1);
  uint wb = workgroup_argmax(vb, ib);
  bool too_fine = false;
  if (w1 != 0xffffffffu && wb != 0xffffffffu) {
    ivec2 k1 = bin_of(w1), kb = bin_of(wb);
    too_fine = power(kb.x, kb.y) > BEYOND_BAND * power(k1.x, k1.y);
  }

  float result[6] = float[6](0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  if (w1 != 0xffffffffu && count > 0.0 && !too_fine) {
    ivec2 p1 = fundamental(bin_of(w1));
    bool coarse = coarser_than_band(p1);
    float p1_r2 = float(p1.x * p1.x + p1.y * p1.y);
    float v2 = -1.0;
    uint i2 = 0u;
    for (uint i = lid; i < total; i += 256u) {
      ivec2 k = bin_of(i);
      if (!in_band(k.x, k.y)) continue;
      float dot_k = float(k.x * p1.x + k.y * p1.y);
      if (dot_k * dot_k >= COS2_MAX * float(k.x * k.x + k.y * k.y) * p1_r2) continue;
      float v = power(k.x, k.y);
      if (v > v2) {
        v2 = v;
        i2 = i;
      }
    }
    uint w2 = workgroup_argmax(v2, i2);
    ivec2 p2 = w2 != 0xffffffffu ? fundamental(bin_of(w2)) : ivec2(0);
    if (w2 != 0xffffffffu && !coarse && !coarser_than_band(p2)) {
      vec2 f1 = refine(p1), f2 = refine(p2);
      if (atan(f1.y, f1.x) > atan(f2.y, f2.x)) {
        vec2 t = f1;
        f1 = f2;
        f2 = t;
      }
      result[0] = f1.x;
      result[1] = f1.y;
      result[2] = f2.x;
      result[3] = f2.y;
      result[4] = min(1.0, (energy3x3(p1) + energy3x3(p2)) / energy);
      result[5] = min(power(p1.x, p1.y), power(p2.x, p2.y)) / (energy / count);
    }
  }
  if (lid == 0u) {
    for (uint j = 0u; j < 6u; ++j) lattices[roi * 8u + j] = result[j];  // 6, 7: extract pass
  }
}
