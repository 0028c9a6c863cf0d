#version 450
// S1/S2 prior maps, one 16x16 tile per workgroup. Every pixel of the tile is at most `bound` (the
// smallest farthest-tile-corner squared distance over all points) from some point, so a point
// whose nearest tile distance exceeds `bound` cannot be nearest to any pixel: the tile keeps the
// rest (ties included) and each pixel searches only those. Distances are integers, so the result
// is exact; ties go to the lowest point index. The point count is read from a parameter buffer
// when the dispatch runs, so a stream recorded once follows a count that changes every frame; it
// is clamped to the points buffer, so a stale count never reads past it.

layout(local_size_x = 16, local_size_y = 16) in;
layout(constant_id = 0) const int WIDTH = 320;
layout(constant_id = 1) const int HEIGHT = 240;
layout(constant_id = 2) const float INV_TWO_SIGMA2 = 0.005;

layout(std430, binding = 0) readonly buffer Points {
  float pts[];
};  // x_px, y_px, depth_m
layout(std430, binding = 1) writeonly buffer Out {
  float values[];
};
layout(std430, binding = 2) readonly buffer Params {
  uint num_points;
};  // SparsePriorParams
layout(push_constant) uniform Push {
  uint out_offset;
};

const uint kMaxPoints = 1024;
shared ivec2 cand_xy[kMaxPoints];
shared uint cand_index[kMaxPoints];
shared uint bound;
shared uint num_cand;

ivec2 snapped(uint i) {
  ivec2 p = ivec2(floor(vec2(pts[3 * i], pts[3 * i + 1]) + 0.5));
  return clamp(p, ivec2(0), ivec2(WIDTH - 1, HEIGHT - 1));
}

void main() {
  uint lid = gl_LocalInvocationIndex;
  uint n = min(min(num_points, kMaxPoints), uint(pts.length()) / 3u);
  ivec2 lo = ivec2(gl_WorkGroupID.xy) * 16;
  ivec2 hi = min(lo + 15, ivec2(WIDTH - 1, HEIGHT - 1));
  if (lid == 0) {
    bound = 0xffffffffu;
    num_cand = 0;
  }
  barrier();
  for (uint i = lid; i < n; i += 256u) {
    ivec2 d = max(abs(snapped(i) - lo), abs(snapped(i) - hi));
    atomicMin(bound, uint(d.x * d.x + d.y * d.y));
  }
  barrier();
  uint b = bound;
  for (uint i = lid; i < n; i += 256u) {
    ivec2 p = snapped(i);
    ivec2 d = max(max(lo - p, p - hi), ivec2(0));
    if (uint(d.x * d.x + d.y * d.y) <= b) {
      uint slot = atomicAdd(num_cand, 1u);
      cand_xy[slot] = p;
      cand_index[slot] = i;
    }
  }
  barrier();

  ivec2 px = lo + ivec2(gl_LocalInvocationID.xy);
  if (px.x >= WIDTH || px.y >= HEIGHT) return;
  uint best = uint(WIDTH * WIDTH + HEIGHT * HEIGHT);
  uint label = 0xffffffffu;
  uint count = num_cand;
  for (uint c = 0; c < count; ++c) {
    ivec2 d = px - cand_xy[c];
    uint d2 = uint(d.x * d.x + d.y * d.y);
    uint idx = cand_index[c];
    if (d2 < best || (d2 == best && idx < label)) {
      best = d2;
      label = idx;
    }
  }
  uint plane = uint(WIDTH * HEIGHT);
  uint i = out_offset + uint(px.y * WIDTH + px.x);
  values[i] = label == 0xffffffffu ? 0.0 : pts[3 * label + 2];
  values[i + plane] = exp(-float(best) * INV_TWO_SIGMA2);
}
