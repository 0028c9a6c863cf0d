#version 450
#extension GL_GOOGLE_include_directive : require
// The camera image (grey levels, already quantised) and the net's z-depth, exactly the model of
// sim/render_cpu.cpp in float, with the lamps' veil interpolated from a table of that model
// (sim/lamp_veil_table.h: within 1.5 % of its peak). One invocation renders ROWS pixels of one column, so its 8 x ROWS
// pixel tile shares one list of marine snow spots. Parameters: sim/render_vk.cpp.
//
// Speed on lavapipe (docs/performance.md): every storage-buffer read there is a per-lane loop,
// hundreds of cycles, so everything fixed for the scenario is a specialization constant (folded
// into the code, dead features compiled away) and the per-frame block is read once per
// invocation, not per sample.

layout(local_size_x = 8, local_size_y = 4) in;
layout(constant_id = 0) const uint WIDTH = 720;
layout(constant_id = 1) const uint HEIGHT = 540;
layout(constant_id = 2) const uint SAMPLES = 1;  // per axis
layout(constant_id = 3) const uint NUM_BULGES = 0;
layout(constant_id = 4) const uint NUM_LAMPS = 2;
layout(constant_id = 5) const uint NUM_FISH = 0;
layout(constant_id = 6) const uint FEATURES = 0;  // kFeature* bits below
// Camera.
layout(constant_id = 7) const float FX = 462.0;
layout(constant_id = 8) const float FY = 462.0;
layout(constant_id = 9) const float CX = 359.5;
layout(constant_id = 10) const float CY = 269.5;
layout(constant_id = 11) const float K1 = 0.0;
layout(constant_id = 12) const float K2 = 0.0;
layout(constant_id = 13) const float P1 = 0.0;
layout(constant_id = 14) const float P2 = 0.0;
// Pen (plane: the net is x = PEN_R, a rectangle; a basin wall WALL_GAP behind it).
layout(constant_id = 15) const float PEN_R = 12.0;
layout(constant_id = 16) const float PEN_DEPTH = 15.0;
layout(constant_id = 17) const float PLANE_WIDTH = 4.9;
layout(constant_id = 18) const float PLANE_TOP = 0.5;
layout(constant_id = 19) const float PLANE_HEIGHT = 1.5;
layout(constant_id = 20) const float WALL_GAP = 1.0;
// Net.
layout(constant_id = 21) const float MESH = 0.03;  // bar length (sim/net_mesh.h)
layout(constant_id = 22) const float TWINE = 0.0035;
layout(constant_id = 23) const float KNOT = 0.006;
layout(constant_id = 24) const float ALBEDO = 0.7;
layout(constant_id = 25) const float FOULING = 0.0;
layout(constant_id = 26) const float FOULING_WALL_U = 0.6;  // fouling cell along u on the wall
layout(constant_id = 27) const float FOULING_SCALE = 0.6;
layout(constant_id = 28) const float NA_X = 0.0;  // twine normals, NetLattice::normal_a/b()
layout(constant_id = 29) const float NA_Y = 1.0;
layout(constant_id = 30) const float LATTICE_SCALE = 1.0;  // NetGeometry::lattice_scale()
layout(constant_id = 31) const int FOULING_CELLS = 0;      // NetGeometry::fouling_cells_around()
// Water, light, sensor.
layout(constant_id = 32) const float ATTENUATION = 0.25;
layout(constant_id = 33) const float KD = 0.12;
layout(constant_id = 34) const float LAMP_BACKSCATTER = 0.03;
layout(constant_id = 35) const float AMBIENT = 1.0;
layout(constant_id = 36) const float SURFACE_BRIGHTNESS = 1.5;
layout(constant_id = 37) const float WALL_ALBEDO = 0.3;
layout(constant_id = 38) const float GAIN = 331.5;  // 255 * exposure
layout(constant_id = 39) const float VIGNETTING = 0.3;
layout(constant_id = 40) const float READ_NOISE = 1.5;
layout(constant_id = 41) const float SHOT_NOISE = 0.3;
layout(constant_id = 42) const uint SEED = 0;
layout(constant_id = 43) const float VISIBLE_RANGE = 15.6;
// Bulges: along, depth, amplitude, radius.
layout(constant_id = 44) const float B0A = 0.0;
layout(constant_id = 45) const float B0D = 0.0;
layout(constant_id = 46) const float B0M = 0.0;
layout(constant_id = 47) const float B0R = 1.0;
layout(constant_id = 48) const float B1A = 0.0;
layout(constant_id = 49) const float B1D = 0.0;
layout(constant_id = 50) const float B1M = 0.0;
layout(constant_id = 51) const float B1R = 1.0;
layout(constant_id = 52) const float B2A = 0.0;
layout(constant_id = 53) const float B2D = 0.0;
layout(constant_id = 54) const float B2M = 0.0;
layout(constant_id = 55) const float B2R = 1.0;
layout(constant_id = 56) const float B3A = 0.0;
layout(constant_id = 57) const float B3D = 0.0;
layout(constant_id = 58) const float B3M = 0.0;
layout(constant_id = 59) const float B3R = 1.0;
layout(constant_id = 60) const float B4A = 0.0;
layout(constant_id = 61) const float B4D = 0.0;
layout(constant_id = 62) const float B4M = 0.0;
layout(constant_id = 63) const float B4R = 1.0;
layout(constant_id = 64) const float B5A = 0.0;
layout(constant_id = 65) const float B5D = 0.0;
layout(constant_id = 66) const float B5M = 0.0;
layout(constant_id = 67) const float B5R = 1.0;
layout(constant_id = 68) const float B6A = 0.0;
layout(constant_id = 69) const float B6D = 0.0;
layout(constant_id = 70) const float B6M = 0.0;
layout(constant_id = 71) const float B6R = 1.0;
layout(constant_id = 72) const float B7A = 0.0;
layout(constant_id = 73) const float B7D = 0.0;
layout(constant_id = 74) const float B7M = 0.0;
layout(constant_id = 75) const float B7R = 1.0;
// Lamps, fixed to the body, so constant in the camera frame: position, direction, intensity,
// cos exponent.
layout(constant_id = 76) const float L0PX = 0.0;
layout(constant_id = 77) const float L0PY = 0.0;
layout(constant_id = 78) const float L0PZ = 0.0;
layout(constant_id = 79) const float L0DX = 0.0;
layout(constant_id = 80) const float L0DY = 0.0;
layout(constant_id = 81) const float L0DZ = 1.0;
layout(constant_id = 82) const float L0I = 0.0;
layout(constant_id = 83) const float L0E = 1.0;
layout(constant_id = 84) const float L1PX = 0.0;
layout(constant_id = 85) const float L1PY = 0.0;
layout(constant_id = 86) const float L1PZ = 0.0;
layout(constant_id = 87) const float L1DX = 0.0;
layout(constant_id = 88) const float L1DY = 0.0;
layout(constant_id = 89) const float L1DZ = 1.0;
layout(constant_id = 90) const float L1I = 0.0;
layout(constant_id = 91) const float L1E = 1.0;
layout(constant_id = 92) const float L2PX = 0.0;
layout(constant_id = 93) const float L2PY = 0.0;
layout(constant_id = 94) const float L2PZ = 0.0;
layout(constant_id = 95) const float L2DX = 0.0;
layout(constant_id = 96) const float L2DY = 0.0;
layout(constant_id = 97) const float L2DZ = 1.0;
layout(constant_id = 98) const float L2I = 0.0;
layout(constant_id = 99) const float L2E = 1.0;
layout(constant_id = 100) const float L3PX = 0.0;
layout(constant_id = 101) const float L3PY = 0.0;
layout(constant_id = 102) const float L3PZ = 0.0;
layout(constant_id = 103) const float L3DX = 0.0;
layout(constant_id = 104) const float L3DY = 0.0;
layout(constant_id = 105) const float L3DZ = 1.0;
layout(constant_id = 106) const float L3I = 0.0;
layout(constant_id = 107) const float L3E = 1.0;
// Fish: half length, half thickness, albedo (their poses change per frame: FrameBuf).
layout(constant_id = 108) const float F0L = 1.0;
layout(constant_id = 109) const float F0T = 1.0;
layout(constant_id = 110) const float F0A = 0.0;
layout(constant_id = 111) const float F1L = 1.0;
layout(constant_id = 112) const float F1T = 1.0;
layout(constant_id = 113) const float F1A = 0.0;
layout(constant_id = 114) const float F2L = 1.0;
layout(constant_id = 115) const float F2T = 1.0;
layout(constant_id = 116) const float F2A = 0.0;
layout(constant_id = 117) const float F3L = 1.0;
layout(constant_id = 118) const float F3T = 1.0;
layout(constant_id = 119) const float F3A = 0.0;
layout(constant_id = 120) const float F4L = 1.0;
layout(constant_id = 121) const float F4T = 1.0;
layout(constant_id = 122) const float F4A = 0.0;
layout(constant_id = 123) const float F5L = 1.0;
layout(constant_id = 124) const float F5T = 1.0;
layout(constant_id = 125) const float F5A = 0.0;
layout(constant_id = 126) const float F6L = 1.0;
layout(constant_id = 127) const float F6T = 1.0;
layout(constant_id = 128) const float F6A = 0.0;
layout(constant_id = 129) const float F7L = 1.0;
layout(constant_id = 130) const float F7T = 1.0;
layout(constant_id = 131) const float F7A = 0.0;
// The mesh lattice and its deformation (sim/net_mesh.h, NetLattice).
layout(constant_id = 132) const float NB_X = 1.0;
layout(constant_id = 133) const float NB_Y = 0.0;
layout(constant_id = 134) const float PERIOD = 0.03;  // twine spacing mesh sin(theta)
layout(constant_id = 135) const float NORMALS_DOT = 0.0;
layout(constant_id = 136) const float KNOT_MEAN = 0.0;  // round knot: disc / cell area
layout(constant_id = 137) const float EB_X = 0.7071;    // bisector of the bars
layout(constant_id = 138) const float EB_Y = 0.7071;
layout(constant_id = 139) const float K_STRETCH = 1.0;
layout(constant_id = 140) const float K_ANGLE = 1.0;
layout(constant_id = 141) const float AMP_STRETCH = 0.0;
layout(constant_id = 142) const float AMP_ANGLE = 0.0;
layout(constant_id = 143) const float PH0 = 0.0;
layout(constant_id = 144) const float PH1 = 0.0;
layout(constant_id = 145) const float PH2 = 0.0;
layout(constant_id = 146) const float PH3 = 0.0;
layout(constant_id = 147) const float DEFORM_FADE = 3.0;
layout(constant_id = 148) const float U_AROUND = 0.0;  // the wall's u around the pen
// Fouled patches and clumps, ropes and seams.
layout(constant_id = 149) const float PATCH_THRESHOLD = 2.0;
layout(constant_id = 150) const float CLUMP_CELL_U = 0.012;  // on the wall (closed)
layout(constant_id = 151) const float CLUMP_CELL_V = 0.012;
layout(constant_id = 152) const int CLUMP_CELLS = 0;
layout(constant_id = 153) const float CLUMP_MEAN = 0.0;
layout(constant_id = 154) const float ROPE_U = 1.0;  // on the wall (closed)
layout(constant_id = 155) const float ROPE_V = 1.0;  // spacing_m
layout(constant_id = 156) const float ROPE_WIDTH = 0.02;
layout(constant_id = 157) const float ROPE_ALBEDO = 0.6;
layout(constant_id = 158) const float SEAM_U = 1.0;  // on the wall (closed)
layout(constant_id = 159) const float SEAM_SPACING = 1.0;
layout(constant_id = 160) const float SEAM_WIDTH = 0.01;
// The lamps' veil table (sim/lamp_veil_table.h): its pixel step and nodes along the ray.
layout(constant_id = 161) const uint VEIL_STEP_PX = 16;
layout(constant_id = 162) const uint VEIL_NODES = 64;

const uint ROWS = 8;  // pixels per invocation (render_vk.cpp: kRowsPerInvocation)

// Indexed by unrolled loop counters, so these fold to the constants.
vec4 BULGE(uint i) {
  return i == 0u   ? vec4(B0A, B0D, B0M, B0R)
         : i == 1u ? vec4(B1A, B1D, B1M, B1R)
         : i == 2u ? vec4(B2A, B2D, B2M, B2R)
         : i == 3u ? vec4(B3A, B3D, B3M, B3R)
         : i == 4u ? vec4(B4A, B4D, B4M, B4R)
         : i == 5u ? vec4(B5A, B5D, B5M, B5R)
         : i == 6u ? vec4(B6A, B6D, B6M, B6R)
                   : vec4(B7A, B7D, B7M, B7R);
}
vec3 LAMP_POS(uint i) {
  return i == 0u   ? vec3(L0PX, L0PY, L0PZ)
         : i == 1u ? vec3(L1PX, L1PY, L1PZ)
         : i == 2u ? vec3(L2PX, L2PY, L2PZ)
                   : vec3(L3PX, L3PY, L3PZ);
}
vec3 LAMP_DIR(uint i) {
  return i == 0u   ? vec3(L0DX, L0DY, L0DZ)
         : i == 1u ? vec3(L1DX, L1DY, L1DZ)
         : i == 2u ? vec3(L2DX, L2DY, L2DZ)
                   : vec3(L3DX, L3DY, L3DZ);
}
vec2 LAMP_IE(uint i) {  // intensity, cos exponent
  return i == 0u   ? vec2(L0I, L0E)
         : i == 1u ? vec2(L1I, L1E)
         : i == 2u ? vec2(L2I, L2E)
                   : vec2(L3I, L3E);
}
vec3 FISH(uint i) {  // half length, half thickness, albedo
  return i == 0u   ? vec3(F0L, F0T, F0A)
         : i == 1u ? vec3(F1L, F1T, F1A)
         : i == 2u ? vec3(F2L, F2T, F2A)
         : i == 3u ? vec3(F3L, F3T, F3A)
         : i == 4u ? vec3(F4L, F4T, F4A)
         : i == 5u ? vec3(F5L, F5T, F5A)
         : i == 6u ? vec3(F6L, F6T, F6A)
                   : vec3(F7L, F7T, F7A);
}

// What changes per frame (render_vk.cpp: FrameHeader), then the marine snow spots.
layout(std430, binding = 0) readonly buffer FrameBuf {
  vec4 rot[3];     // rows of R_world_camera; w: camera centre in P
  uvec4 info;      // frame, background radiance (float bits), spot tile columns, unused
  vec4 fish_c[8];  // centre in P
  vec4 fish_a[8];  // unit axis in P
  vec4 spots[];    // x, y, 1 / sigma^2, peak radiance
};
// Per 8 x ROWS tile: begin and end into the spot index list that follows the offsets.
layout(std430, binding = 1) readonly buffer TileBuf {
  uint tiles[];
};
layout(std430, binding = 2) writeonly buffer ImageBuf {
  float image[];
};
layout(std430, binding = 3) writeonly buffer DepthBuf {
  float depth[];
};
// The lamps' veil (sim/lamp_veil_table.h): per 16 x 16 pixel cell and node along the ray, the
// values at the cell's four corners.
layout(std430, binding = 4) readonly buffer VeilBuf {
  vec4 veil[];
};

#include "hash.glsl"

const float kInf = 1e30;
const uint kFeatureNoise = 1u, kFeatureSnow = 2u, kFeaturePlane = 4u, kFeatureBottom = 8u,
           kFeatureWall = 16u, kFeatureFouling = 32u, kFeatureDistortion = 64u,
           kFeatureDeform = 256u, kFeaturePatches = 512u, kFeatureRopes = 1024u,
           kFeatureSeams = 2048u, kFeatureRoundKnots = 4096u,
           kFeatureRadiance = 128u;  // unrounded, noise-free grey for sim/optics.h
bool has(uint feature) {
  return (FEATURES & feature) != 0u;
}
const int kBulgeIterations = 6;  // sim/net_geometry.h
const float kBulgeTolerance = 1e-5;
float circumference() {
  return 6.283185307179586 * PEN_R;
}
const float kSnowCutoff2 = 16.0;  // sim/marine_snow.h: kSnowCutoffSigmas^2

// The frame's block, read once per invocation.
mat3 R_wc;  // columns: camera axes in P (GLSL is column-major; rows are uploaded)
vec3 origin;
vec3 fish_centre[8], fish_axis[8];
float background;

// ---- camera ----
vec2 distort(vec2 xn) {
  float x = xn.x, y = xn.y, r2 = x * x + y * y;
  float radial = 1.0 + K1 * r2 + K2 * r2 * r2;
  return vec2(x * radial + 2.0 * P1 * x * y + P2 * (r2 + 2.0 * x * x),
              y * radial + P1 * (r2 + 2.0 * y * y) + 2.0 * P2 * x * y);
}

vec3 camera_ray(vec2 px) {  // z = 1, as PinholeCamera::ray
  vec2 xd = vec2((px.x - CX) / FX, (px.y - CY) / FY);
  vec2 xn = xd;
  if (has(kFeatureDistortion)) {
    for (int i = 0; i < 20; ++i) xn = xd - (distort(xn) - xn);
  }
  return vec3(xn, 1.0);
}

// ---- net geometry (sim/net_geometry.cpp) ----
float wrap_along(float da) {
  return has(kFeaturePlane) ? da : da - circumference() * round(da / circumference());
}

// A bulge with w < 0 is a fold of half width -w (sim/scenario.h Bulge::fold).
float displacement(float along, float z) {
  float s = 0.0;
  for (uint i = 0u; i < NUM_BULGES; ++i) {
    vec4 b = BULGE(i);
    float da = wrap_along(along - b.x), dz = z - b.y;
    s += b.w < 0.0 ? b.z * max(0.0, 1.0 + abs(da) / b.w)
                   : b.z * exp(-(da * da + dz * dz) / (2.0 * b.w * b.w));
  }
  return s;
}

vec2 displacement_gradient(float along, float z) {
  vec2 g = vec2(0.0);
  for (uint i = 0u; i < NUM_BULGES; ++i) {
    vec4 b = BULGE(i);
    float da = wrap_along(along - b.x), dz = z - b.y, s2 = b.w * b.w;
    if (b.w < 0.0) {
      if (abs(da) < -b.w) g.x += sign(da) * b.z / b.w;
      continue;
    }
    float e = b.z * exp(-(da * da + dz * dz) / (2.0 * s2));
    g += vec2(-da / s2 * e, -dz / s2 * e);
  }
  return g;
}

// NetGeometry::fold_arc_offset: a fold's surface length over the wall's from its line to x (the
// sides mirror each other; one Simpson panel, sim/net_geometry.cpp fold_extra_from_line).
float fold_extra(vec4 b, float at) {
  float r = -b.w, inv_radius = has(kFeaturePlane) ? 0.0 : 1.0 / PEN_R;
  float k = 1.0 - b.z * (1.0 - abs(at) / r) * inv_radius, g = b.z / r;
  return sqrt(k * k + g * g) - 1.0;
}

float fold_arc_offset(float along) {
  float s = 0.0;
  for (uint i = 0u; i < NUM_BULGES; ++i) {
    vec4 b = BULGE(i);
    if (b.w >= 0.0) continue;
    float x = clamp(along - b.x, b.w, -b.w);
    s += x / 6.0 * (fold_extra(b, 0.0) + 4.0 * fold_extra(b, 0.5 * x) + fold_extra(b, x));
  }
  return s;
}

float along_of(vec3 q) {
  return has(kFeaturePlane) ? q.y : PEN_R * atan(q.y, q.x);
}

struct Hit {
  float t;
  vec3 point, normal, tu, tv;
  float u, v;
  bool wall;
};

bool intersect_wall_or_plane(vec3 o, vec3 d, out Hit h) {
  float offset = 0.0, t = -1.0, along = 0.0, disp = 0.0;
  vec3 q = o;
  for (int i = 0; i < kBulgeIterations; ++i) {
    float r = PEN_R - offset;
    if (has(kFeaturePlane)) {
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
  h.u = (along + fold_arc_offset(along)) * LATTICE_SCALE;
  h.v = q.z;
  h.tv = vec3(0.0, 0.0, 1.0);
  h.wall = !has(kFeaturePlane);
  if (has(kFeaturePlane)) {
    h.tu = vec3(0.0, 1.0, 0.0);
    h.normal = normalize(vec3(1.0, g.x, g.y));
  } else {
    vec3 er = vec3(normalize(q.xy), 0.0), et = vec3(-er.y, er.x, 0.0);
    float k = (PEN_R - disp) / PEN_R;
    h.tu = LATTICE_SCALE * et;
    h.normal = normalize(k * er + g.x * et + k * g.y * vec3(0.0, 0.0, 1.0));
  }
  return true;
}

bool intersect_net(vec3 o, vec3 d, out Hit h) {
  bool hit = intersect_wall_or_plane(o, d, h);
  if (has(kFeaturePlane)) {
    return hit && abs(h.point.y) <= PLANE_WIDTH / 2.0 && h.point.z >= PLANE_TOP &&
           h.point.z <= PLANE_TOP + PLANE_HEIGHT;
  }
  if (hit && h.point.z <= PEN_DEPTH) return true;
  if (!has(kFeatureBottom) || !(d.z > 0.0)) return false;
  float t = (PEN_DEPTH - o.z) / d.z;
  if (!(t > 0.0)) return false;
  h.t = t;
  h.point = o + t * d;
  if (length(h.point.xy) > PEN_R) return false;
  h.normal = vec3(0.0, 0.0, 1.0);
  h.u = h.point.x;
  h.v = h.point.y;
  h.tu = vec3(1.0, 0.0, 0.0);
  h.tv = vec3(0.0, 1.0, 0.0);
  h.wall = false;
  return true;
}

float intersect_back_wall(vec3 o, vec3 d) {
  if (!has(kFeatureWall) || !(d.x > 0.0)) return kInf;
  float t = (PEN_R + WALL_GAP - o.x) / d.x;
  return t > 0.0 ? t : kInf;
}

float intersect_fish(uint i, vec3 o, vec3 d) {
  vec3 axis = fish_axis[i];
  vec3 q = o - fish_centre[i];
  float qa = dot(q, axis), da = dot(d, axis);
  vec3 qp = q - qa * axis, dp = d - da * axis;
  float ia = 1.0 / (FISH(i).x * FISH(i).x);
  float ib = 1.0 / (FISH(i).y * FISH(i).y);
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

uint wrap_cell(int i, int n) {
  return uint(n > 0 ? ((i % n) + n) % n : i);
}

float value_noise(float u, float v, float scale_u, float scale_v, int wrap_u, uint seed) {
  float x = u / scale_u, y = v / scale_v;
  float fx = floor(x), fy = floor(y);
  uint ix = wrap_cell(int(fx), wrap_u), ix1 = wrap_cell(int(fx) + 1, wrap_u), iy = uint(int(fy));
  float tx = x - fx, ty = y - fy;
  float sx = tx * tx * (3.0 - 2.0 * tx), sy = ty * ty * (3.0 - 2.0 * ty);
  float l00 = unit_float(hash2(ix, iy, seed)), l10 = unit_float(hash2(ix1, iy, seed));
  float l01 = unit_float(hash2(ix, iy + 1u, seed)), l11 = unit_float(hash2(ix1, iy + 1u, seed));
  float a = l00 + sx * (l10 - l00);
  float b = l01 + sx * (l11 - l01);
  return a + sy * (b - a);
}

float ambient(float z) {
  return AMBIENT * exp(-KD * max(z, 0.0));
}

// q_w: the point in P (for its depth); q_c and n_in in the camera frame, where the lamps are
// constants; `n_in` points into the surface; twine is lit from most sides.
float irradiance(float z_w, vec3 q_c, vec3 n_in, bool twine) {
  float e = ambient(z_w);
  for (uint i = 0u; i < NUM_LAMPS; ++i) {
    vec3 v = q_c - LAMP_POS(i);
    float r2 = dot(v, v), r = sqrt(r2);
    vec3 vh = v / r;
    float ca = dot(vh, LAMP_DIR(i));
    if (ca <= 0.0) continue;
    float cosi = dot(n_in, vh);
    float shade = twine ? 0.5 + 0.5 * abs(cosi) : max(cosi, 0.0);
    e += LAMP_IE(i).x * shade * exp(LAMP_IE(i).y * log(ca) - ATTENUATION * r) / max(r2, 0.01);
  }
  return e;
}

float smoothstep_(float lo, float hi, float x) {
  float t = clamp((x - lo) / (hi - lo), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// The deformed lattice coordinates x' and dx'/dx (NetLattice::deform).
vec2 deform(vec2 p, bool wall, out mat2 J) {
  vec2 eb = vec2(EB_X, EB_Y), ep = vec2(-EB_Y, EB_X);
  float xi = dot(eb, p), eta = dot(ep, p);
  float a1 = K_STRETCH * xi + PH0, a2 = K_STRETCH * eta + PH1;
  float a3 = K_ANGLE * xi + PH2, a4 = K_ANGLE * eta + PH3;
  float c1 = cos(a1), s1 = sin(a1), c2 = cos(a2), s2 = sin(a2);
  float c3 = cos(a3), s3 = sin(a3), c4 = cos(a4), s4 = sin(a4);
  vec2 Dl = vec2(AMP_STRETCH / K_STRETCH * s1 * c2 - AMP_ANGLE / K_ANGLE * s3 * c4,
                 AMP_STRETCH / K_STRETCH * c1 * s2 + AMP_ANGLE / K_ANGLE * c3 * s4);
  // Columns: d/dxi, d/deta of the local displacement.
  mat2 G = mat2(
      AMP_STRETCH * c1 * c2 - AMP_ANGLE * c3 * c4, -AMP_STRETCH * s1 * s2 - AMP_ANGLE * s3 * s4,
      -AMP_STRETCH * s1 * s2 + AMP_ANGLE * s3 * s4, AMP_STRETCH * c1 * c2 + AMP_ANGLE * c3 * c4);
  mat2 R = mat2(eb, ep);
  vec2 D = R * Dl;
  mat2 grad = R * G * transpose(R);
  if (wall && U_AROUND > 0.0) {
    float uw = p.x - U_AROUND * round(p.x / U_AROUND);
    float dist = U_AROUND / 2.0 - abs(uw);
    float t = clamp(dist / DEFORM_FADE, 0.0, 1.0);
    float w = t * t * (3.0 - 2.0 * t);
    float dw = (dist > 0.0 && dist < DEFORM_FADE)
                   ? -6.0 * t * (1.0 - t) / DEFORM_FADE * (uw < 0.0 ? -1.0 : 1.0)
                   : 0.0;
    grad = w * grad;
    grad[0] += D * dw;
    D *= w;
  }
  J = mat2(1.0) + grad;
  return p + D;
}

// Twine (and clump) coverage, the round knots' share of it, the rope coverage over it and the
// fouled-patch weight (sim/render_cpu.cpp, Tracer::net_look).
vec4 net_look(Hit h, vec3 Dw, float s) {
  vec3 dDx = R_wc[0] / FX, dDy = R_wc[1] / FY;
  float denom = dot(Dw, h.normal);
  vec3 px = s * (dDx - dot(dDx, h.normal) / denom * Dw);
  vec3 py = s * (dDy - dot(dDy, h.normal) / denom * Dw);
  float n = float(SAMPLES);
  vec2 fx = vec2(dot(px, h.tu), dot(px, h.tv)), fy = vec2(dot(py, h.tu), dot(py, h.tv));
  float hu = (abs(fx.x) + abs(fy.x)) / n, hv = (abs(fx.y) + abs(fy.y)) / n;
  vec2 x = vec2(h.u, h.v);
  if (has(kFeatureDeform)) {
    mat2 J;
    x = deform(x, h.wall, J);
    fx = J * fx;
    fy = J * fy;
  }
  vec2 na = vec2(NA_X, NA_Y), nb = vec2(NB_X, NB_Y);
  float qa = dot(na, x), qb = dot(nb, x);
  float ha = (abs(dot(na, fx)) + abs(dot(na, fy))) / n;
  float hb = (abs(dot(nb, fx)) + abs(dot(nb, fy))) / n;
  float w = TWINE, fouled = 0.0, knot = 0.0, rope = 0.0;
  if (has(kFeaturePatches)) {
    float su = h.wall ? FOULING_WALL_U : FOULING_SCALE;
    int wrap = h.wall ? FOULING_CELLS : 0;
    fouled = smoothstep_(PATCH_THRESHOLD - 0.12, PATCH_THRESHOLD + 0.12,
                         value_noise(h.u, h.v, su, FOULING_SCALE, wrap, SEED ^ kStreamPatches));
    w = min(w * (1.0 + 1.5 * fouled), max(w, 0.45 * PERIOD));
  }
  float ca = pulse_coverage(qa, ha, PERIOD, w, -w / 2.0);
  float cb = pulse_coverage(qb, hb, PERIOD, w, -w / 2.0);
  float cover = 1.0 - (1.0 - cb) * (1.0 - ca);
  if (has(kFeatureSeams)) {
    float period = h.wall ? SEAM_U : SEAM_SPACING;
    cover = 1.0 -
            (1.0 - cover) * (1.0 - pulse_coverage(h.u, hu, period, SEAM_WIDTH, -SEAM_WIDTH / 2.0));
  }
  float da = qa - PERIOD * round(qa / PERIOD), db = qb - PERIOD * round(qb / PERIOD);
  if (!has(kFeatureRoundKnots)) {
    cover = max(cover, pulse_coverage(qb, hb, PERIOD, KNOT, -KNOT / 2.0) *
                           pulse_coverage(qa, ha, PERIOD, KNOT, -KNOT / 2.0));
  } else {
    float g = NORMALS_DOT;
    float d = sqrt(max(0.0, (da * da + db * db - 2.0 * g * da * db) / (1.0 - g * g)));
    float f = 0.5 * (ha + hb);
    float sharp = clamp((KNOT / 2.0 - d) / max(f, 1e-12) + 0.5, 0.0, 1.0);
    float fade = clamp((f - 0.25 * PERIOD) / (0.5 * PERIOD), 0.0, 1.0);
    knot = sharp + fade * (KNOT_MEAN - sharp);
    cover = max(cover, knot);
  }
  if (has(kFeaturePatches) && fouled > 0.0) {
    float cu = h.wall ? CLUMP_CELL_U : CLUMP_CELL_V;
    int wrap = h.wall ? CLUMP_CELLS : 0;
    float noise = value_noise(h.u, h.v, cu, CLUMP_CELL_V, wrap, SEED ^ kStreamClumps);
    float reach = 1.0 - smoothstep_(w / 2.0, w / 2.0 + 0.2 * PERIOD, min(abs(da), abs(db)));
    float sharp = smoothstep_(0.6, 0.85, noise) * reach;
    float fade = clamp((max(ha, hb) - 0.15 * PERIOD) / (0.35 * PERIOD), 0.0, 1.0);
    cover = 1.0 - (1.0 - cover) * (1.0 - fouled * (sharp + fade * (CLUMP_MEAN - sharp)));
  }
  if (has(kFeatureRopes)) {
    float period_u = h.wall ? ROPE_U : ROPE_V;
    rope = 1.0 - (1.0 - pulse_coverage(h.u, hu, period_u, ROPE_WIDTH, -ROPE_WIDTH / 2.0)) *
                     (1.0 - pulse_coverage(h.v, hv, ROPE_V, ROPE_WIDTH, -ROPE_WIDTH / 2.0));
  }
  return vec4(cover, knot, rope, fouled);
}

// First opaque surface (water surface, fish, basin wall): distance and radiance.
// d: unit ray in P, dc: the same in the camera frame.
vec2 first_opaque(vec3 d, vec3 dc) {
  float best = kInf;
  int kind = 0;  // 0 none, 1 surface, 2 fish, 3 wall
  uint fish = 0u;
  if (d.z < 0.0) {
    best = -origin.z / d.z;
    kind = 1;
  }
  for (uint i = 0u; i < NUM_FISH; ++i) {
    float t = intersect_fish(i, origin, d);
    if (t < best) {
      best = t;
      kind = 2;
      fish = i;
    }
  }
  float tw = intersect_back_wall(origin, d);
  if (tw < best) {
    best = tw;
    kind = 3;
  }
  if (kind == 0) return vec2(kInf, background);
  vec3 q = origin + best * d;
  float J;
  if (kind == 1) {
    J = SURFACE_BRIGHTNESS * AMBIENT;
  } else if (kind == 2) {
    vec3 axis = fish_axis[fish];
    vec3 r = q - fish_centre[fish];
    float ra = dot(r, axis);
    float hl = FISH(fish).x, ht = FISH(fish).y;
    vec3 grad = (r - ra * axis) / (ht * ht) + ra * axis / (hl * hl);
    J = FISH(fish).z * irradiance(q.z, best * dc, -normalize(grad * R_wc), false);
  } else {
    J = WALL_ALBEDO * irradiance(q.z, best * dc, vec3(1.0, 0.0, 0.0) * R_wc, false);
  }
  float T = exp(-ATTENUATION * best);
  return vec2(best, J * T + background * (1.0 - T));
}

// The lamps' beams scattered once towards the camera along the ray up to t_end (cut at the
// visible range): sim/lamp_veil.cpp's quadrature, tabulated per scenario (sim/lamp_veil_table.h)
// because the lamps ride with the camera, interpolated bilinearly over the pixel and linearly in
// ln(1 + t / kLampVeilScale) along the ray.
const float kLampVeilScale = 0.1;  // sim/lamp_veil.h
float lamp_backscatter(vec2 px, float t_end) {
  if (!(LAMP_BACKSCATTER > 0.0) || NUM_LAMPS == 0u) return 0.0;
  uint cells_x = (WIDTH + VEIL_STEP_PX - 1u) / VEIL_STEP_PX;
  uint cells_y = (HEIGHT + VEIL_STEP_PX - 1u) / VEIL_STEP_PX;
  float w_max = log(1.0 + VISIBLE_RANGE / kLampVeilScale);
  float u = log(1.0 + min(t_end, VISIBLE_RANGE) / kLampVeilScale) / w_max * float(VEIL_NODES - 1u);
  uint j = min(uint(u), VEIL_NODES - 2u);
  vec2 g = max((px + 0.5) / float(VEIL_STEP_PX), vec2(0.0));
  uvec2 c = min(uvec2(g), uvec2(cells_x - 1u, cells_y - 1u));
  vec2 f = g - vec2(c);
  uint k = (c.y * cells_x + c.x) * VEIL_NODES + j;
  vec4 v = mix(veil[k], veil[k + 1u], u - float(j));  // corners x0y0, x1y0, x0y1, x1y1
  return mix(mix(v.x, v.y, f.x), mix(v.z, v.w, f.x), f.y);
}

// px: where the ray leaves the image (pixel coordinates).
float radiance(vec2 px, out float depth_m) {
  vec3 Dc = camera_ray(px);
  float len = length(Dc);
  vec3 Dw = R_wc * Dc, d = Dw / len, dc = Dc / len;
  vec2 opaque = first_opaque(d, dc);
  Hit h;
  depth_m = 0.0;
  if (!intersect_net(origin, d, h) || h.t >= opaque.x) {
    return opaque.y + lamp_backscatter(px, opaque.x);
  }
  if (h.t <= VISIBLE_RANGE) depth_m = h.t / len * Dc.z;
  vec4 look = net_look(h, Dw, h.t / len);
  float cover = look.x;
  float albedo = ALBEDO;
  if (has(kFeatureFouling)) {
    float su = h.wall ? FOULING_WALL_U : FOULING_SCALE;
    int wrap = h.wall ? FOULING_CELLS : 0;
    albedo *= 1.0 - FOULING * value_noise(h.u, h.v, su, FOULING_SCALE, wrap, SEED ^ kStreamFouling);
  }
  // sim/net_mesh.h: kFouledBrightening, kFouledAlbedo, kKnotGain.
  albedo += look.w * 0.6 * (0.85 - albedo);
  if (look.y > 0.0) albedo *= 1.0 + 0.15 * look.y / cover;
  float T = exp(-ATTENUATION * h.t);
  // The normal in the camera frame: v * R_wc = transpose(R_wc) * v.
  float E = irradiance(h.point.z, h.t * dc, h.normal * R_wc, true);
  float twine = albedo * E * T + background * (1.0 - T);
  float L = cover * twine + (1.0 - cover) * opaque.y;
  if (look.z > 0.0)
    L = look.z * (ROPE_ALBEDO * E * T + background * (1.0 - T)) + (1.0 - look.z) * L;
  return L + lamp_backscatter(px, h.t);
}

float gaussian(uint h1, uint h2) {
  float u1 = (float(h1 >> 8) + 0.5) * (1.0 / 16777216.0);
  return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * unit_float(h2));
}

void main() {
  uint x = gl_GlobalInvocationID.x, y0 = gl_GlobalInvocationID.y * ROWS;
  if (x >= WIDTH || y0 >= HEIGHT) return;
  R_wc = transpose(mat3(rot[0].xyz, rot[1].xyz, rot[2].xyz));
  origin = vec3(rot[0].w, rot[1].w, rot[2].w);
  for (uint i = 0u; i < NUM_FISH; ++i) {
    fish_centre[i] = fish_c[i].xyz;
    fish_axis[i] = fish_a[i].xyz;
  }
  uvec4 frame = info;
  background = uintBitsToFloat(frame.y);
  uint frame_key = hash3(frame.x, SEED, kStreamNoise);
  uint tile = (y0 / ROWS) * frame.z + x / 8u;
  uint spot_begin = 0u, spot_end = 0u;
  if (has(kFeatureSnow)) {
    spot_begin = tiles[tile];
    spot_end = tiles[tile + 1u];
  }
  float n = float(SAMPLES);
  for (uint row = 0u; row < ROWS; ++row) {
    uint y = y0 + row;
    if (y >= HEIGHT) break;
    float L = 0.0, z = 0.0, sample_z;
    for (uint sy = 0u; sy < SAMPLES; ++sy) {
      for (uint sx = 0u; sx < SAMPLES; ++sx) {
        vec2 px =
            vec2(float(x) + (float(sx) + 0.5) / n - 0.5, float(y) + (float(sy) + 0.5) / n - 0.5);
        L += radiance(px, sample_z);
        if (2u * sx + 1u == SAMPLES && 2u * sy + 1u == SAMPLES) z = sample_z;
      }
    }
    L /= n * n;
    vec3 D0 = camera_ray(vec2(x, y));
    if (SAMPLES % 2u == 0u) radiance(vec2(x, y), z);
    uint i = y * WIDTH + x;
    depth[i] = z;
    if (has(kFeatureSnow)) {
      float snow = 0.0;
      for (uint k = spot_begin; k < spot_end; ++k) {
        vec4 s = spots[tiles[k]];
        float dx = float(x) - s.x, dy = float(y) - s.y;
        float q = (dx * dx + dy * dy) * s.z;
        if (q < kSnowCutoff2) snow += s.w * exp(-0.5 * q);
      }
      L += snow;
    }
    L *= pow(1.0 / length(D0), 4.0 * VIGNETTING);
    float grey = GAIN * L;
    if (has(kFeatureNoise)) {
      float sigma = sqrt(READ_NOISE * READ_NOISE + SHOT_NOISE * SHOT_NOISE * max(grey, 0.0));
      uint h = hash2(i, frame_key, 0u);
      grey += sigma * gaussian(h, hash32(h));
    }
    image[i] = has(kFeatureRadiance) ? grey : clamp(floor(grey + 0.5), 0.0, 255.0);
  }
}
