// Body of shaders/nn/<name>.comp and <name>_f16.comp (STORE: see nn_types.glsl).
#include "nn_types.glsl"
// Resize of the last two axes: MODE 0 nearest (asymmetric, floor), 1 linear half_pixel,
// 2 linear align_corners; linear source coordinates clamped to [0, size - 1].
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint MODE = 0;
layout(std430, binding = 0) readonly buffer X { STORE x[]; };
layout(std430, binding = 1) writeonly buffer Y { STORE y[]; };
layout(push_constant) uniform Push { uint NC, H, W, OH, OW; };
#include "index.glsl"

void tap(uint o, uint n_in, uint n_out, out uint i0, out uint i1, out float f) {
  float s;
  if (MODE == 2) {
    s = n_out > 1 ? float(o) * (float(n_in - 1) / float(n_out - 1)) : 0.0;
  } else {
    s = (float(o) + 0.5) * (float(n_in) / float(n_out)) - 0.5;
  }
  s = clamp(s, 0.0, float(n_in - 1));
  i0 = uint(floor(s));
  i1 = min(i0 + 1, n_in - 1);
  f = s - float(i0);
}

void process(uint i) {
  uint ox = i % OW, oy = (i / OW) % OH, p = i / (OW * OH);
  uint base = p * H * W;
  if (MODE == 0) {
    uint sy = min(H - 1, uint(floor(float(oy) * (float(H) / float(OH)))));
    uint sx = min(W - 1, uint(floor(float(ox) * (float(W) / float(OW)))));
    y[i] = ST(LD(x[base + sy * W + sx]));
    return;
  }
  uint y0, y1, x0, x1;
  float fy, fx;
  tap(oy, H, OH, y0, y1, fy);
  tap(ox, W, OW, x0, x1, fx);
  float top = LD(x[base + y0 * W + x0]) * (1.0 - fx) + LD(x[base + y0 * W + x1]) * fx;
  float bot = LD(x[base + y1 * W + x0]) * (1.0 - fx) + LD(x[base + y1 * W + x1]) * fx;
  y[i] = ST(top * (1.0 - fy) + bot * fy);
}

void main() {
  for (uint i = flat_index(); i < NC * OH * OW; i += flat_stride()) process(i);
}
