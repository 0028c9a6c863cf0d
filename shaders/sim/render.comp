#version 450
#extension GL_GOOGLE_include_directive : require
// One invocation per pixel: the camera image (grey levels, already quantised) and the net's
// z-depth, exactly the model of sim/render_cpu.cpp in float. Parameters: sim/render_vk.cpp.

layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const uint WIDTH = 720;
layout(constant_id = 1) const uint HEIGHT = 540;
layout(constant_id = 2) const uint SAMPLES = 2;  // per axis
// The scene's structure is fixed per scenario: as constants, loops unroll with constant indices
// and unused features compile away (llvmpipe pays for every dynamically indexed read).
layout(constant_id = 3) const uint NUM_BULGES = 0;
layout(constant_id = 4) const uint NUM_LAMPS = 2;
layout(constant_id = 5) const uint NUM_FISH = 0;
layout(constant_id = 6) const uint FEATURES = 0;  // kFeature* bits below

struct Params {
  vec4 cam;         // fx, fy, cx, cy
  vec4 dist;        // k1, k2, p1, p2
  vec4 rot[3];      // rows of R_world_camera
  vec4 origin;      // camera centre in P, w: net visible range
  vec4 pen;         // radius, depth, bottom (0/1), shape (0 cylinder, 1 plane)
  vec4 plane;       // width, top, height, wall gap
  vec4 net;         // mesh, twine width, knot size, albedo
  vec4 net2;        // fouling, fouling scale, cos(mesh angle), sin(mesh angle)
  vec4 water;       // attenuation c, Kd, background radiance, lamp backscatter
  vec4 light;       // ambient E0, surface brightness, wall albedo, snow brightness * light
  vec4 camera;      // 255 * exposure, vignetting, read noise, shot noise
  uvec4 counts;     // frame, seed, marine snow density as float bits, unused
  vec4 bulge[8];    // along, depth, amplitude, radius
  vec4 lamp_pos[4]; // position, intensity
  vec4 lamp_dir[4]; // direction, cos exponent
  vec4 fish_c[8];   // centre, albedo
  vec4 fish_a[8];   // axis, half length
  vec4 fish_t[8];   // half thickness
};

layout(std430, binding = 0) readonly buffer ParamBuf { Params p; };
layout(std430, binding = 1) writeonly buffer ImageBuf { float image[]; };
layout(std430, binding = 2) writeonly buffer DepthBuf { float depth[]; };

#include "hash.glsl"

const float kInf = 1e30;
const uint kFeatureNoise = 1u, kFeatureSnow = 2u, kFeaturePlane = 4u, kFeatureBottom = 8u,
           kFeatureWall = 16u, kFeatureFouling = 32u, kFeatureDistortion = 64u;
bool has(uint feature) { return (FEATURES & feature) != 0u; }
const int kBulgeIterations = 6;  // sim/net_geometry.h
const float kBulgeTolerance = 1e-5;
const int kSnowCellPx = 24;

// ---- camera ----
vec2 distort(vec2 xn) {
  float x = xn.x, y = xn.y, r2 = x * x + y * y;
  float radial = 1.0 + p.dist.x * r2 + p.dist.y * r2 * r2;
  return vec2(x * radial + 2.0 * p.dist.z * x * y + p.dist.w * (r2 + 2.0 * x * x),
              y * radial + p.dist.z * (r2 + 2.0 * y * y) + 2.0 * p.dist.w * x * y);
}

vec3 camera_ray(vec2 px) {  // z = 1, as PinholeCamera::ray
  vec2 xd = vec2((px.x - p.cam.z) / p.cam.x, (px.y - p.cam.w) / p.cam.y);
  vec2 xn = xd;
  if (has(kFeatureDistortion)) {
    for (int i = 0; i < 20; ++i) xn = xd - (distort(xn) - xn);
  }
  return vec3(xn, 1.0);
}

vec3 to_world(vec3 v) {
  return vec3(dot(p.rot[0].xyz, v), dot(p.rot[1].xyz, v), dot(p.rot[2].xyz, v));
}

// ---- net geometry (sim/net_geometry.cpp) ----
float displacement(float along, float z) {
  float s = 0.0;
  for (uint i = 0u; i < NUM_BULGES; ++i) {
    vec4 b = p.bulge[i];
    float da = along - b.x, dz = z - b.y;
    s += b.z * exp(-(da * da + dz * dz) / (2.0 * b.w * b.w));
  }
  return s;
}

vec2 displacement_gradient(float along, float z) {
  vec2 g = vec2(0.0);
  for (uint i = 0u; i < NUM_BULGES; ++i) {
    vec4 b = p.bulge[i];
    float da = along - b.x, dz = z - b.y, s2 = b.w * b.w;
    float e = b.z * exp(-(da * da + dz * dz) / (2.0 * s2));
    g += vec2(-da / s2 * e, -dz / s2 * e);
  }
  return g;
}

bool is_plane() { return has(kFeaturePlane); }

float along_of(vec3 q) {
  return is_plane() ? q.y : p.pen.x * atan(q.y, q.x);
}

struct Hit {
  float t;
  vec3 point, normal, tu, tv;
  float u, v;
};

bool intersect_wall_or_plane(vec3 o, vec3 d, out Hit h) {
  float R = p.pen.x, offset = 0.0, t = -1.0, along = 0.0, disp = 0.0;
  vec3 q = o;
  for (int i = 0; i < kBulgeIterations; ++i) {
    float r = R - offset;
    if (is_plane()) {
      if (!(d.x > 0.0)) return false;
      t = (r - o.x) / d.x;
    } else {
      float a = d.x * d.x + d.y * d.y;
      if (a < 1e-12) return false;
      float b = o.x * d.x + o.y * d.y;
      float c = o.x * o.x + o.y * o.y - r * r;
      float disc = b * b - a * c;
      if (disc < 0.0) return false;
      t = (-b + sqrt(disc)) / a;
    }
    if (!(t > 0.0)) return false;
    q = o + t * d;
    along = along_of(q);
    if (NUM_BULGES == 0u) break;
    disp = displacement(along, q.z);
    if (abs(disp - offset) < kBulgeTolerance) break;
    offset = disp;
  }
  h.t = t;
  h.point = q;
  vec2 g = displacement_gradient(along, q.z);
  h.u = along;
  h.v = q.z;
  h.tv = vec3(0.0, 0.0, 1.0);
  if (is_plane()) {
    h.tu = vec3(0.0, 1.0, 0.0);
    h.normal = normalize(vec3(1.0, g.x, g.y));
  } else {
    vec3 er = vec3(normalize(q.xy), 0.0), et = vec3(-er.y, er.x, 0.0);
    float k = (R - disp) / R;
    h.tu = et;
    h.normal = normalize(k * er + g.x * et + k * g.y * vec3(0.0, 0.0, 1.0));
  }
  return true;
}

bool intersect_net(vec3 o, vec3 d, out Hit h) {
  bool hit = intersect_wall_or_plane(o, d, h);
  if (is_plane()) {
    return hit && abs(h.point.y) <= p.plane.x / 2.0 && h.point.z >= p.plane.y &&
           h.point.z <= p.plane.y + p.plane.z;
  }
  if (hit && h.point.z <= p.pen.y) return true;
  if (!has(kFeatureBottom) || !(d.z > 0.0)) return false;
  float t = (p.pen.y - o.z) / d.z;
  if (!(t > 0.0)) return false;
  h.t = t;
  h.point = o + t * d;
  if (length(h.point.xy) > p.pen.x) return false;
  h.normal = vec3(0.0, 0.0, 1.0);
  h.u = h.point.x;
  h.v = h.point.y;
  h.tu = vec3(1.0, 0.0, 0.0);
  h.tv = vec3(0.0, 1.0, 0.0);
  return true;
}

float intersect_back_wall(vec3 o, vec3 d) {
  if (!has(kFeatureWall) || !(d.x > 0.0)) return kInf;
  float t = (p.pen.x + p.plane.w - o.x) / d.x;
  return t > 0.0 ? t : kInf;
}

float intersect_fish(uint i, vec3 o, vec3 d) {
  vec3 axis = p.fish_a[i].xyz;
  vec3 q = o - p.fish_c[i].xyz;
  float qa = dot(q, axis), da = dot(d, axis);
  vec3 qp = q - qa * axis, dp = d - da * axis;
  float ia = 1.0 / (p.fish_a[i].w * p.fish_a[i].w);
  float ib = 1.0 / (p.fish_t[i].x * p.fish_t[i].x);
  float A = dot(dp, dp) * ib + da * da * ia;
  float B = dot(qp, dp) * ib + qa * da * ia;
  float C = dot(qp, qp) * ib + qa * qa * ia - 1.0;
  float disc = B * B - A * C;
  if (disc < 0.0) return kInf;
  float t = (-B - sqrt(disc)) / A;
  return t > 0.0 ? t : kInf;
}

// ---- shading (sim/render_cpu.cpp) ----
float pulse_integral(float y, float period, float width) {
  float n = floor(y / period);
  return n * width + min(y - n * period, width);
}

float pulse_coverage(float x, float h, float period, float width, float offset) {
  if (width <= 0.0) return 0.0;
  x -= offset;
  x -= period * floor(x / period);
  if (h < 1e-6 * period) return x < width ? 1.0 : 0.0;
  return (pulse_integral(x + h / 2.0, period, width) - pulse_integral(x - h / 2.0, period, width)) /
         h;
}

float value_noise(float u, float v, float scale, uint seed) {
  float x = u / scale, y = v / scale;
  float fx = floor(x), fy = floor(y);
  uint ix = uint(int(fx)), iy = uint(int(fy));
  float tx = x - fx, ty = y - fy;
  float sx = tx * tx * (3.0 - 2.0 * tx), sy = ty * ty * (3.0 - 2.0 * ty);
  float l00 = unit_float(hash3(ix, iy, seed)), l10 = unit_float(hash3(ix + 1u, iy, seed));
  float l01 = unit_float(hash3(ix, iy + 1u, seed)), l11 = unit_float(hash3(ix + 1u, iy + 1u, seed));
  float a = l00 + sx * (l10 - l00);
  float b = l01 + sx * (l11 - l01);
  return a + sy * (b - a);
}

float ambient(float z) {
  return p.light.x * exp(-p.water.y * max(z, 0.0));
}

float irradiance(vec3 q, vec3 n_in, bool twine) {
  float e = ambient(q.z);
  for (uint i = 0u; i < NUM_LAMPS; ++i) {
    vec3 v = q - p.lamp_pos[i].xyz;
    float r2 = dot(v, v), r = sqrt(r2);
    vec3 vh = v / r;
    float ca = dot(vh, p.lamp_dir[i].xyz);
    if (ca <= 0.0) continue;
    float cosi = dot(n_in, vh);
    float shade = twine ? 0.5 + 0.5 * abs(cosi) : max(cosi, 0.0);
    e += p.lamp_pos[i].w * shade * exp(p.lamp_dir[i].w * log(ca) - p.water.x * r) / max(r2, 0.01);
  }
  return e;
}

float net_coverage(Hit h, vec3 Dw, float s, vec3 dDx, vec3 dDy) {
  float denom = dot(Dw, h.normal);
  vec3 px = s * (dDx - dot(dDx, h.normal) / denom * Dw);
  vec3 py = s * (dDy - dot(dDy, h.normal) / denom * Dw);
  float n = float(SAMPLES);
  float hu0 = (abs(dot(px, h.tu)) + abs(dot(py, h.tu))) / n;
  float hv0 = (abs(dot(px, h.tv)) + abs(dot(py, h.tv))) / n;
  float ca = p.net2.z, sa = p.net2.w;
  float u = ca * h.u + sa * h.v, v = -sa * h.u + ca * h.v;
  float hu = abs(ca) * hu0 + abs(sa) * hv0, hv = abs(sa) * hu0 + abs(ca) * hv0;
  float P = p.net.x, w = p.net.y, k = p.net.z;
  float cu = pulse_coverage(u, hu, P, w, -w / 2.0);
  float cv = pulse_coverage(v, hv, P, w, -w / 2.0);
  float knot = pulse_coverage(u, hu, P, k, -k / 2.0) * pulse_coverage(v, hv, P, k, -k / 2.0);
  return max(1.0 - (1.0 - cu) * (1.0 - cv), knot);
}

// First opaque surface (water surface, fish, basin wall): distance, radiance, transmittance.
vec3 first_opaque(vec3 o, vec3 d) {
  float best = kInf;
  int kind = 0;  // 0 none, 1 surface, 2 fish, 3 wall
  uint fish = 0u;
  if (d.z < 0.0) {
    best = -o.z / d.z;
    kind = 1;
  }
  for (uint i = 0u; i < NUM_FISH; ++i) {
    float t = intersect_fish(i, o, d);
    if (t < best) {
      best = t;
      kind = 2;
      fish = i;
    }
  }
  float tw = intersect_back_wall(o, d);
  if (tw < best) {
    best = tw;
    kind = 3;
  }
  float B = p.water.z;
  if (kind == 0) return vec3(kInf, B, 0.0);
  vec3 q = o + best * d;
  float J;
  if (kind == 1) {
    J = p.light.y * p.light.x;
  } else if (kind == 2) {
    vec3 axis = p.fish_a[fish].xyz;
    vec3 r = q - p.fish_c[fish].xyz;
    float ra = dot(r, axis);
    float ht = p.fish_t[fish].x, hl = p.fish_a[fish].w;
    vec3 grad = (r - ra * axis) / (ht * ht) + ra * axis / (hl * hl);
    J = p.fish_c[fish].w * irradiance(q, -normalize(grad), false);
  } else {
    J = p.light.z * irradiance(q, vec3(1.0, 0.0, 0.0), false);
  }
  float T = exp(-p.water.x * best);
  return vec3(best, J * T + B * (1.0 - T), T);
}

float lamp_backscatter(vec3 d, float T_end) {
  float s = 0.0;
  for (uint i = 0u; i < NUM_LAMPS; ++i) s += p.lamp_pos[i].w * 0.5 * (1.0 + dot(d, p.lamp_dir[i].xyz));
  return p.water.w * s * (1.0 - T_end);
}

float radiance(vec3 o, vec3 Dc, vec3 dDx, vec3 dDy, out float depth_m) {
  float len = length(Dc);
  vec3 Dw = to_world(Dc), d = Dw / len;
  vec3 opaque = first_opaque(o, d);
  Hit h;
  depth_m = 0.0;
  if (!intersect_net(o, d, h) || h.t >= opaque.x) return opaque.y + lamp_backscatter(d, opaque.z);
  if (h.t <= p.origin.w) depth_m = h.t / len * Dc.z;
  float cover = net_coverage(h, Dw, h.t / len, dDx, dDy);
  float albedo = p.net.w;
  if (has(kFeatureFouling)) {
    albedo *= 1.0 - p.net2.x * value_noise(h.u, h.v, p.net2.y, p.counts.y ^ kStreamFouling);
  }
  float T = exp(-p.water.x * h.t);
  float twine = albedo * irradiance(h.point, h.normal, true) * T + p.water.z * (1.0 - T);
  return cover * twine + (1.0 - cover) * opaque.y + lamp_backscatter(d, T);
}

float snow(uint x, uint y) {
  // The 2x2 cells nearest to the pixel (sim/render_cpu.cpp).
  int cx = (int(x) + kSnowCellPx / 2) / kSnowCellPx - 1;
  int cy = (int(y) + kSnowCellPx / 2) / kSnowCellPx - 1;
  float density = uintBitsToFloat(p.counts.z);
  float s = 0.0;
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      uint cell = uint(cx + dx) + (uint(cy + dy) << 16);
      uint h = hash3(cell, p.counts.x, p.counts.y ^ kStreamSnow);
      if (unit_float(h) >= density) continue;
      h = hash32(h);
      float sx = (float(cx + dx) + unit_float(h)) * float(kSnowCellPx);
      h = hash32(h);
      float sy = (float(cy + dy) + unit_float(h)) * float(kSnowCellPx);
      h = hash32(h);
      float u = unit_float(h);
      float radius = 0.7 + 2.5 * u * u;
      float bright = 0.4 + 0.6 * unit_float(hash32(h));
      float ddx = float(x) - sx, ddy = float(y) - sy;
      s += bright * exp(-(ddx * ddx + ddy * ddy) / (2.0 * radius * radius));
    }
  }
  return p.light.w * s;
}

float gaussian(uint h1, uint h2) {
  float u1 = (float(h1 >> 8) + 0.5) * (1.0 / 16777216.0);
  return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * unit_float(h2));
}

void main() {
  uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
  if (x >= WIDTH || y >= HEIGHT) return;
  vec3 o = p.origin.xyz;
  vec3 dDx = to_world(vec3(1.0 / p.cam.x, 0.0, 0.0));
  vec3 dDy = to_world(vec3(0.0, 1.0 / p.cam.y, 0.0));
  float n = float(SAMPLES);
  float L = 0.0, z = 0.0, sample_z;
  for (uint sy = 0u; sy < SAMPLES; ++sy) {
    for (uint sx = 0u; sx < SAMPLES; ++sx) {
      vec2 px = vec2(float(x) + (float(sx) + 0.5) / n - 0.5, float(y) + (float(sy) + 0.5) / n - 0.5);
      L += radiance(o, camera_ray(px), dDx, dDy, sample_z);
      if (2u * sx + 1u == SAMPLES && 2u * sy + 1u == SAMPLES) z = sample_z;
    }
  }
  L /= n * n;
  vec3 D0 = camera_ray(vec2(x, y));
  if (SAMPLES % 2u == 0u) radiance(o, D0, dDx, dDy, z);
  uint i = y * WIDTH + x;
  depth[i] = z;
  if (has(kFeatureSnow)) L += snow(x, y);
  L *= pow(1.0 / length(D0), 4.0 * p.camera.y);
  float grey = p.camera.x * L;
  if (has(kFeatureNoise)) {
    uint stream = p.counts.y ^ kStreamNoise;
    float sigma = sqrt(p.camera.z * p.camera.z + p.camera.w * p.camera.w * max(grey, 0.0));
    grey += sigma * gaussian(hash3(i, p.counts.x, stream), hash3(i, p.counts.x, ~stream));
  }
  image[i] = clamp(floor(grey + 0.5), 0.0, 255.0);
}
