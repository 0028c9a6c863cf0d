// Reads one pixel from an image packed into 32-bit words (8-bit: 4 pixels a word, 16-bit: 2),
// little-endian, row-major, stride == width. Expects `words[]`, WIDTH and BITS in scope.
#ifndef PENSIGHT_PIXELS_GLSL
#define PENSIGHT_PIXELS_GLSL

float load_pixel(uint x, uint y) {
  uint i = y * WIDTH + x;
  if (BITS == 8) return float((words[i >> 2] >> ((i & 3u) * 8u)) & 0xffu);
  return float((words[i >> 1] >> ((i & 1u) * 16u)) & 0xffffu);
}

#endif
