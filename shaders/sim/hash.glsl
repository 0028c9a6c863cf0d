// The renderer's random numbers; the same functions and constants as sim/sim_hash.h.
uint hash32(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

uint hash3(uint a, uint b, uint c) {
  return hash32(a ^ hash32(b ^ hash32(c + 0x9e3779b9u)));
}

uint hash2(uint a, uint b, uint key) {
  return hash32(a * 0x9e3779b1u + b * 0x85ebca77u + key);
}

float unit_float(uint h) {
  return float(h >> 8) * (1.0 / 16777216.0);
}

const uint kStreamNoise = 0x1b873593u;
const uint kStreamSnow = 0x5a5a5a5au;
const uint kStreamFouling = 0x27d4eb2fu;
const uint kStreamPatches = 0xd3a2646cu;
const uint kStreamClumps = 0xfd7046c5u;
