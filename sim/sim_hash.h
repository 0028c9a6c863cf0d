#pragma once
// The random numbers of the renderer: a stateless integer hash of (index, frame, stream), so the
// CPU reference and the Vulkan shader (shaders/sim/hash.glsl, same constants) draw identical
// values for every pixel, frame and seed, in any order and on any number of threads.
#include <cstdint>

namespace pensight::sim {

// "lowbias32" integer finaliser (Wellons): full avalanche, cheap on GPUs.
constexpr uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

constexpr uint32_t hash3(uint32_t a, uint32_t b, uint32_t c) {
  return hash32(a ^ hash32(b ^ hash32(c + 0x9e3779b9u)));
}

// One finaliser round over a linear mix of a 2-D lattice point: enough for value noise and
// per-pixel noise, and a third of hash3's work (the renderer draws these per sample).
constexpr uint32_t hash2(uint32_t a, uint32_t b, uint32_t key) {
  return hash32(a * 0x9e3779b1u + b * 0x85ebca77u + key);
}

// Uniform in [0, 1) with 24 bits, exactly representable in float.
constexpr double unit_float(uint32_t h) {
  return static_cast<double>(h >> 8) * (1.0 / 16777216.0);
}

constexpr uint32_t fold_seed(uint64_t seed) {
  return static_cast<uint32_t>(seed ^ (seed >> 32));
}

// Independent streams of the renderer.
inline constexpr uint32_t kStreamNoise = 0x1b873593u, kStreamSnow = 0x5a5a5a5au,
                          kStreamFouling = 0x27d4eb2fu, kStreamDeform = 0x165667b1u,
                          kStreamPatches = 0xd3a2646cu, kStreamClumps = 0xfd7046c5u;

}  // namespace pensight::sim
