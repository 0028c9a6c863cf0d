// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// Transposed convolution as a gather: each output element sums the input pixels whose strided
// footprint covers it. Weights are [C, K/G, KH, KW] (ONNX layout).
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint OCB = 1;
layout(constant_id = 1) const uint ACT = 0;
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
  uint k = gl_GlobalInvocationID.y;
  uint n = gl_GlobalInvocationID.z;
  if (p >= OH * OW || k >= K) return;
  int oy = int(p / OW), ox = int(p % OW);
  uint cog = K / G, cig = C / G;
  uint g = k / cog, kk = k % cog;
  float acc = 0.0;
  for (uint ky = 0; ky < KH; ++ky) {
    int ty = oy + int(PT) - int(ky * DH);
    if (ty < 0 || ty % int(SH) != 0) continue;
    int iy = ty / int(SH);
    if (iy >= int(H)) continue;
    for (uint kx = 0; kx < KW; ++kx) {
      int tx = ox + int(PL) - int(kx * DW);
      if (tx < 0 || tx % int(SW) != 0) continue;
      int ix = tx / int(SW);
      if (ix >= int(Wd)) continue;
      for (uint c = 0; c < cig; ++c) {
        uint ci = g * cig + c;
        acc += LD(x[((n * C + ci) * H + uint(iy)) * Wd + uint(ix)]) *
               LD(w[((ci * cog + kk) * KH + ky) * KW + kx]);
      }
    }
  }
  y[((n * K + k) * OH * OW) + p] = ST(activate(acc + LD(bias[k])));
}
