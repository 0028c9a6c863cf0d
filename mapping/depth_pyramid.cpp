#include "mapping/depth_pyramid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "runtime/simd_clones.h"

namespace pensight::mapping {
namespace {

// Level 0, written so the compiler vectorises it (AVX2 in the x86-64-v3 clone): x <= FLT_MAX is
// false for NaN and infinity, x >= min_range and x > 0 for NaN too.
PENSIGHT_SIMD_CLONES void base_level(const float* __restrict depth, size_t n, float min_range_m,
                                     float max_range_m, float* __restrict near_m,
                                     float* __restrict far_m) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  constexpr float kMax = std::numeric_limits<float>::max();
  for (size_t i = 0; i < n; ++i) {
    const float d = depth[i];
    const bool valid = d >= min_range_m && d > 0 && d <= kMax;
    near_m[i] = valid ? (d > max_range_m ? kInf : d) : 0.0f;
    far_m[i] = valid ? std::min(d, max_range_m) : 0.0f;
  }
}

}  // namespace

void DepthPyramid::build(const ImageF32& depth_m, float min_range_m, float max_range_m) {
  width_ = depth_m.width;
  height_ = depth_m.height;
  int w = width_, h = height_;
  size_t n_levels = 1;
  while (w > 1 || h > 1) {
    w = (w + 1) / 2;
    h = (h + 1) / 2;
    ++n_levels;
  }
  levels_.resize(n_levels);
  w = width_;
  h = height_;
  for (Level& l : levels_) {
    l.width = w;
    l.height = h;
    l.near_m.resize(static_cast<size_t>(w) * h);
    l.far_m.resize(static_cast<size_t>(w) * h);
    w = (w + 1) / 2;
    h = (h + 1) / 2;
  }
  base_level(depth_m.pixels.data(), depth_m.pixels.size(), min_range_m, max_range_m,
             levels_[0].near_m.data(), levels_[0].far_m.data());
  for (size_t k = 1; k < levels_.size(); ++k) {
    const Level& fine = levels_[k - 1];
    Level& coarse = levels_[k];
    for (int y = 0; y < coarse.height; ++y) {
      const int y0 = 2 * y, y1 = std::min(2 * y + 1, fine.height - 1);
      for (int x = 0; x < coarse.width; ++x) {
        const int x0 = 2 * x, x1 = std::min(2 * x + 1, fine.width - 1);
        const size_t a = static_cast<size_t>(y0) * fine.width,
                     b = static_cast<size_t>(y1) * fine.width;
        const size_t o = static_cast<size_t>(y) * coarse.width + x;
        coarse.near_m[o] = std::min(
            {fine.near_m[a + x0], fine.near_m[a + x1], fine.near_m[b + x0], fine.near_m[b + x1]});
        coarse.far_m[o] = std::max(
            {fine.far_m[a + x0], fine.far_m[a + x1], fine.far_m[b + x0], fine.far_m[b + x1]});
      }
    }
  }
}

DepthPyramid::Bounds DepthPyramid::query(int x0, int y0, int x1, int y1) const {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, width_ - 1);
  y1 = std::min(y1, height_ - 1);
  if (x1 < x0 || y1 < y0) return {0.0f, 0.0f};
  const int extent = std::max(x1 - x0, y1 - y0) + 1;
  int k = 0;
  while ((2 << k) < extent) ++k;
  const Level& l = levels_[static_cast<size_t>(k)];
  Bounds b{std::numeric_limits<float>::infinity(), 0.0f};
  for (int by = y0 >> k; by <= y1 >> k; ++by) {
    for (int bx = x0 >> k; bx <= x1 >> k; ++bx) {
      const size_t o = static_cast<size_t>(by) * l.width + bx;
      b.near_m = std::min(b.near_m, l.near_m[o]);
      b.far_m = std::max(b.far_m, l.far_m[o]);
    }
  }
  return b;
}

}  // namespace pensight::mapping
