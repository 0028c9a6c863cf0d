// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// Direct grouped 2-D convolution with fused bias and activation. Each invocation computes a
// register block of OCB consecutive output channels x PXB horizontally adjacent output pixels,
// so every input value and weight it loads feeds several multiply-adds.
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint OCB = 4;
layout(constant_id = 1) const uint ACT = 0;  // see act.glsl
layout(constant_id = 2) const float ALPHA = 0.0;
layout(constant_id = 3) const float BETA = 0.0;
layout(constant_id = 4) const uint PXB = 4;

layout(std430, binding = 0) readonly buffer X { STORE x[]; };
layout(std430, binding = 1) readonly buffer W { STORE w[]; };
layout(std430, binding = 2) readonly buffer B { STORE bias[]; };
layout(std430, binding = 3) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push {
  uint C, H, Wd, K, OH, OW, KH, KW, SH, SW, DH, DW, PT, PL, G;
};

#include "act.glsl"

void main() {
  uint blocks_x = (OW + PXB - 1) / PXB;
  uint p = gl_GlobalInvocationID.x;
  uint k0 = gl_GlobalInvocationID.y * OCB;
  uint n = gl_GlobalInvocationID.z;
  if (p >= OH * blocks_x || k0 >= K) return;
  uint oy = p / blocks_x, ox0 = (p % blocks_x) * PXB;
  uint cog = K / G, cig = C / G;
  uint g = k0 / cog;
  uint kn = min(OCB, K - k0), pn = min(PXB, OW - ox0);
  float acc[OCB][PXB];
  for (uint j = 0; j < OCB; ++j)
    for (uint q = 0; q < PXB; ++q) acc[j][q] = 0.0;
  int iy0 = int(oy * SH) - int(PT), ix0 = int(ox0 * SW) - int(PL);
  uint wstride = cig * KH * KW;
  for (uint c = 0; c < cig; ++c) {
    uint xbase = (n * C + g * cig + c) * H * Wd;
    for (uint ky = 0; ky < KH; ++ky) {
      int iy = iy0 + int(ky * DH);
      if (iy < 0 || iy >= int(H)) continue;
      uint row = xbase + uint(iy) * Wd;
      for (uint kx = 0; kx < KW; ++kx) {
        float v[PXB];
        for (uint q = 0; q < PXB; ++q) {
          int ix = ix0 + int(q * SW + kx * DW);
          v[q] = (q < pn && ix >= 0 && ix < int(Wd)) ? LD(x[row + uint(ix)]) : 0.0;
        }
        uint widx = ((k0 * cig + c) * KH + ky) * KW + kx;
        for (uint j = 0; j < OCB; ++j) {
          float wv = j < kn ? LD(w[widx + j * wstride]) : 0.0;
          for (uint q = 0; q < PXB; ++q) acc[j][q] += v[q] * wv;
        }
      }
    }
  }
  for (uint j = 0; j < kn; ++j) {
    uint k = k0 + j;
    float b = LD(bias[k]);
    uint base = ((n * K + k) * OH + oy) * OW + ox0;
    for (uint q = 0; q < pn; ++q) y[base + q] = ST(activate(acc[j][q] + b));
  }
}
