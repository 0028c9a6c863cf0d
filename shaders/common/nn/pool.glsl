// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// MaxPool / AveragePool (padding excluded from the max; from the average unless INCLUDE_PAD).
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint IS_MAX = 1;
layout(constant_id = 1) const uint INCLUDE_PAD = 0;
layout(std430, binding = 0) readonly buffer X { STORE x[]; };
layout(std430, binding = 1) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push { uint NC, H, W, OH, OW, KH, KW, SH, SW, PT, PL; };
#include "index.glsl"
void process(uint i) {
  uint ox = i % OW, oy = (i / OW) % OH, p = i / (OW * OH);
  float acc = IS_MAX == 1 ? -3.402823466e38 : 0.0;
  uint count = 0;
  for (uint ky = 0; ky < KH; ++ky) {
    int iy = int(oy * SH + ky) - int(PT);
    if (iy < 0 || iy >= int(H)) continue;
    for (uint kx = 0; kx < KW; ++kx) {
      int ix = int(ox * SW + kx) - int(PL);
      if (ix < 0 || ix >= int(W)) continue;
      float v = LD(x[p * H * W + uint(iy) * W + uint(ix)]);
      acc = IS_MAX == 1 ? max(acc, v) : acc + v;
      ++count;
    }
  }
  if (IS_MAX == 0) acc /= float(INCLUDE_PAD == 1 ? KH * KW : count);
  y[i] = ST(acc);
}

void main() {
  for (uint i = flat_index(); i < NC * OH * OW; i += flat_stride()) process(i);
}
