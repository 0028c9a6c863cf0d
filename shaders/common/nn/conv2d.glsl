// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// Direct grouped 2-D convolution with fused bias and activation. Each invocation computes OCB
// consecutive output channels of one output pixel (inputs loaded once for all of them).
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint OCB = 4;
layout(constant_id = 1) const uint ACT = 0;  // 0 none, 1 relu, 2 clip, 3 leaky, 4 sigmoid
layout(constant_id = 2) const float ALPHA = 0.0;
layout(constant_id = 3) const float BETA = 0.0;

layout(std430, binding = 0) readonly buffer X { STORE x[]; };
layout(std430, binding = 1) readonly buffer W { STORE w[]; };
layout(std430, binding = 2) readonly buffer B { STORE bias[]; };
layout(std430, binding = 3) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push {
  uint C, H, Wd, K, OH, OW, KH, KW, SH, SW, DH, DW, PT, PL, G;
};

#include "act.glsl"

void main() {
  uint p = gl_GlobalInvocationID.x;
  uint k0 = gl_GlobalInvocationID.y * OCB;
  uint n = gl_GlobalInvocationID.z;
  if (p >= OH * OW || k0 >= K) return;
  uint oy = p / OW, ox = p % OW;
  uint cog = K / G, cig = C / G;
  uint g = k0 / cog;
  float acc[OCB];
  for (uint j = 0; j < OCB; ++j) acc[j] = 0.0;
  int iy0 = int(oy * SH) - int(PT), ix0 = int(ox * SW) - int(PL);
  for (uint c = 0; c < cig; ++c) {
    uint xbase = (n * C + g * cig + c) * H * Wd;
    for (uint ky = 0; ky < KH; ++ky) {
      int iy = iy0 + int(ky * DH);
      if (iy < 0 || iy >= int(H)) continue;
      for (uint kx = 0; kx < KW; ++kx) {
        int ix = ix0 + int(kx * DW);
        if (ix < 0 || ix >= int(Wd)) continue;
        float v = LD(x[xbase + uint(iy) * Wd + uint(ix)]);
        uint widx = ((k0 * cig + c) * KH + ky) * KW + kx;
        for (uint j = 0; j < OCB; ++j) {
          if (k0 + j < K) acc[j] += v * LD(w[widx + j * cig * KH * KW]);
        }
      }
    }
  }
  for (uint j = 0; j < OCB; ++j) {
    uint k = k0 + j;
    if (k < K) y[((n * K + k) * OH * OW) + p] = ST(activate(acc[j] + LD(bias[k])));
  }
}
